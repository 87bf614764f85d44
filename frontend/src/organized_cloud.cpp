#include "planemap/frontend/organized_cloud.h"

#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include "cpu_features.h"

#ifdef PLANEMAP_AVX2_LOOPS
#include <immintrin.h>
#endif

namespace planemap {
namespace {

// One row's depth and colour, and where its points go. y_factor: (v - cy) / fy.
struct CloudRow {
  const float* depth;
  const Rgb8* color;  // null: no colour
  pcl::PointXYZRGB* points;
  int width;
  double cx, inv_fx, y_factor;
  float z_min, z_max;
};

// Pixel u's colour into its point, if the row has colour (both loops below).
inline void CopyColor(const CloudRow& row, int u) {
  if (row.color == nullptr) return;
  const Rgb8& c = row.color[u];
  row.points[u].r = c[0];
  row.points[u].g = c[1];
  row.points[u].b = c[2];
}

// Pixels [u0, width) of the row: x = (u - cx) / fx z, y = (v - cy) / fy z in double, then float.
void FillRow(const CloudRow& row, int u0) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int u = u0; u < row.width; ++u) {
    pcl::PointXYZRGB& p = row.points[u];
    const float z = row.depth[u];
    CopyColor(row, u);
    if (!(z >= row.z_min && z <= row.z_max)) {  // also false for NaN
      p.x = p.y = p.z = nan;
      continue;
    }
    p.x = static_cast<float>((u - row.cx) * row.inv_fx * z);
    p.y = static_cast<float>(row.y_factor * z);
    p.z = z;
  }
}

#ifdef PLANEMAP_AVX2_LOOPS
#pragma GCC push_options
#pragma GCC target("avx2")
// FillRow four pixels at a time: the same double products, rounded to float the same way, each
// point's x, y, z and PCL's fourth float (1, as constructed) written as one vector.
void FillRowAvx2(const CloudRow& row) {
  static_assert(sizeof(pcl::PointXYZRGB) == 32 && offsetof(pcl::PointXYZRGB, data) == 0, "x, y, z, pad lead each point");
  const __m128 nan = _mm_set1_ps(std::numeric_limits<float>::quiet_NaN()), one = _mm_set1_ps(1.0f);
  const __m128 z_min = _mm_set1_ps(row.z_min), z_max = _mm_set1_ps(row.z_max);
  const __m256d cx = _mm256_set1_pd(row.cx), inv_fx = _mm256_set1_pd(row.inv_fx), y_factor = _mm256_set1_pd(row.y_factor);
  const __m256d step = _mm256_set1_pd(4.0);
  __m256d u4 = _mm256_setr_pd(0.0, 1.0, 2.0, 3.0);
  int u = 0;
  for (; u + 4 <= row.width; u += 4, u4 = _mm256_add_pd(u4, step)) {
    const __m128 z = _mm_loadu_ps(row.depth + u);
    const __m128 valid = _mm_and_ps(_mm_cmp_ps(z, z_min, _CMP_GE_OQ), _mm_cmp_ps(z, z_max, _CMP_LE_OQ));
    const __m256d zd = _mm256_cvtps_pd(z);
    __m128 x = _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_mul_pd(_mm256_sub_pd(u4, cx), inv_fx), zd));
    __m128 y = _mm256_cvtpd_ps(_mm256_mul_pd(y_factor, zd));
    x = _mm_blendv_ps(nan, x, valid);
    y = _mm_blendv_ps(nan, y, valid);
    __m128 zz = _mm_blendv_ps(nan, z, valid);
    __m128 w = one;
    _MM_TRANSPOSE4_PS(x, y, zz, w);  // now each the x, y, z, 1 of one point
    _mm_storeu_ps(row.points[u].data, x);
    _mm_storeu_ps(row.points[u + 1].data, y);
    _mm_storeu_ps(row.points[u + 2].data, zz);
    _mm_storeu_ps(row.points[u + 3].data, w);
    for (int k = u; k < u + 4; ++k) CopyColor(row, k);
  }
  FillRow(row, u);
}
#pragma GCC pop_options
#endif

}  // namespace

bool OrganizedCloudHasAvx2() { return CpuHasAvx2(); }

Cloud::Ptr MakeOrganizedCloud(const RgbdFrame& frame, const CameraIntrinsics& camera, const CloudConfig& config,
                              bool avx2) {
  const int w = camera.width, h = camera.height;
  if (frame.depth.width() != w || frame.depth.height() != h) {
    throw std::invalid_argument("frame " + std::to_string(frame.index) + ": depth is " +
                                std::to_string(frame.depth.width()) + "x" + std::to_string(frame.depth.height()) +
                                ", camera is " + std::to_string(w) + "x" + std::to_string(h));
  }
  const bool has_color = frame.color.width() == w && frame.color.height() == h;
  auto cloud = std::make_shared<Cloud>(w, h);
  cloud->is_dense = false;
  CloudRow row;
  row.width = w;
  row.cx = camera.cx;
  row.inv_fx = 1.0 / camera.fx;
  row.z_min = static_cast<float>(config.min_depth), row.z_max = static_cast<float>(config.max_depth);
  const double inv_fy = 1.0 / camera.fy;
  for (int v = 0; v < h; ++v) {
    row.depth = frame.depth.data() + static_cast<std::size_t>(v) * w;
    row.color = has_color ? frame.color.data() + static_cast<std::size_t>(v) * w : nullptr;
    row.points = cloud->points.data() + static_cast<std::size_t>(v) * w;
    row.y_factor = (v - camera.cy) * inv_fy;
#ifdef PLANEMAP_AVX2_LOOPS
    if (avx2) {
      FillRowAvx2(row);
      continue;
    }
#endif
    FillRow(row, 0);
  }
  (void)avx2;
  return cloud;
}

Cloud::Ptr MakeOrganizedCloud(const RgbdFrame& frame, const CameraIntrinsics& camera, const CloudConfig& config) {
  return MakeOrganizedCloud(frame, camera, config, OrganizedCloudHasAvx2());
}

}  // namespace planemap
