// Step 4's pixel loop (assign_pixels.h), twice: the scalar loop, and the same loop with AVX2 for
// runs of four pixels. Compiled with -ffp-contract=off (frontend/CMakeLists.txt): products and
// sums stay separate instructions in both, so both give the same doubles.
#include "assign_pixels.h"

#include <cmath>
#include <cstddef>
#include <cstring>

#include "planemap/core/detected_plane.h"

#include "cpu_features.h"

#ifdef PLANEMAP_AVX2_LOOPS
#include <immintrin.h>
#endif

namespace planemap {
namespace {

// The region of the nearest of a cell's `count` candidate planes within `limit` of (x, y, z), or
// -1; *close_planes: how many are within it.
inline int Nearest(const AssignCandidate* candidate, int count, double x, double y, double z, double limit,
                   int* close_planes) {
  if (count == 1) {  // most cells: one plane around them (the loop's test, unrolled)
    const AssignCandidate& f = candidate[0];
    const bool near = std::abs(f.nx * x + f.ny * y + f.nz * z + f.d) < limit;
    *close_planes = near;
    return near ? f.region : -1;
  }
  double best = limit;
  int best_region = -1;
  for (int k = 0; k < count; ++k) {
    const AssignCandidate& f = candidate[k];
    const double distance = std::abs(f.nx * x + f.ny * y + f.nz * z + f.d);
    if (distance < limit) ++*close_planes;
    if (distance < best) {
      best = distance;
      best_region = f.region;
    }
  }
  return best_region;
}

}  // namespace

void AssignPixelsScalar(const AssignGrid& grid, const AssignOutput& out) {
  const int w = grid.w, h = grid.h, cs = grid.cs, cw = grid.cw;
  // The region the last pixels went to: its sums, count and box are kept here, in registers,
  // while pixels go on joining it (the same additions in the same order as into its entry).
  int current = -1;
  WeightedSums s = WeightedSums::Zero();
  double count_held = 0.0;
  Eigen::Vector3d low, high;
  auto hold = [&](int region) {
    if (current >= 0) {
      out.sums[current] = s;
      out.count[current] = count_held;
      out.bounds[current].low = low;
      out.bounds[current].high = high;
    }
    current = region;
    if (current < 0) return;
    s = out.sums[current];
    count_held = out.count[current];
    low = out.bounds[current].low;
    high = out.bounds[current].high;
  };
  // In locals: the inlier lists' growth writes memory the grid might be in, as far as the
  // compiler knows, and would have them read again for every pixel.
  const double inlier_base = grid.inlier_base, inlier_quadratic = grid.inlier_quadratic;
  const AssignCandidate* const candidates = grid.candidates;
  const int* const first = grid.first;
  for (int v = 0; v < h; ++v) {
    const int cell_row = (v / cs) * cw;
    const std::uint8_t* usable_row = grid.usable + static_cast<size_t>(v) * w;
    const pcl::PointXYZRGB* point_row = grid.points + static_cast<size_t>(v) * w;
    for (int cx = 0; cx < cw; ++cx) {
      const AssignCandidate* candidate = candidates + first[cell_row + cx];
      const int count = first[cell_row + cx + 1] - first[cell_row + cx];
      if (count == 0) continue;
      for (int u = cx * cs, u_end = std::min(w, u + cs); u < u_end; ++u) {
        if (!usable_row[u]) continue;
        const pcl::PointXYZRGB& p = point_row[u];
        const double x = p.x, y = p.y, z = p.z;
        const double limit = GrowsWithDepth(inlier_base, inlier_quadratic, z);
        int close_planes = 0;
        const int best_region = Nearest(candidate, count, x, y, z, limit, &close_planes);
        if (best_region < 0) continue;
        if (best_region != current) hold(best_region);
        out.inliers[best_region].push_back(v * w + u);
        const Eigen::Vector3d q(x, y, z);
        low = low.cwiseMin(q);
        high = high.cwiseMax(q);
        if (close_planes > 1) {
          out.ambiguous[v * w + u] = 1;
          continue;
        }
        const double wt = DepthNoiseWeight(z), wx = wt * x, wy = wt * y, wz = wt * z;
        s += (WeightedSums() << wt, wx, wy, wz, wx * x, wx * y, wx * z, wy * y, wy * z, wz * z).finished();
        count_held += 1;
      }
    }
  }
  hold(-1);
}

bool AssignPixelsHasAvx2() { return CpuHasAvx2(); }

#ifdef PLANEMAP_AVX2_LOOPS
// The scalar loop, with AVX2 where a cell has one candidate plane and four pixels in a row are
// usable and all near it (most of a frame): their distances to the plane are taken together, and
// then each pixel does what the scalar loop does, in the same order. The held region's ten sums
// lie side by side in three vectors, each sum still added to one pixel after another:
//   first  += (w, wx, wy, wz)                              w = 1 / z^4, wx = w x, ...
//   second += (wx, wx, wx, wy) * (x, y, z, y)              -> wxx, wxy, wxz, wyy
//   third  += (wy, wz, ., .) * (z, z, ., .)                -> wyz, wzz
// so every sum gets the same additions of the same products as in the scalar loop; its box is
// (x, y, z, .) vectors, min(p, low) keeping low on a tie as std::min does.
#pragma GCC push_options
#pragma GCC target("avx2")
void AssignPixelsAvx2(const AssignGrid& grid, const AssignOutput& out) {
  static_assert(sizeof(pcl::PointXYZRGB) == 32 && offsetof(pcl::PointXYZRGB, data) == 0, "x, y, z, pad lead each point");
  static_assert(sizeof(WeightedSums) == 10 * sizeof(double), "ten doubles side by side");
  const int w = grid.w, h = grid.h, cs = grid.cs, cw = grid.cw;
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256d sign = _mm256_set1_pd(-0.0);
  int current = -1;
  __m256d first_sums = _mm256_setzero_pd(), second_sums = _mm256_setzero_pd(), third_sums = _mm256_setzero_pd();
  double count_held = 0.0;
  __m256d low = _mm256_setzero_pd(), high = _mm256_setzero_pd();
  std::vector<int>* list = nullptr;  // the held region's inliers
  auto hold = [&](int region) {
    if (current >= 0) {
      double* s = out.sums[current].data();
      _mm256_storeu_pd(s, first_sums);
      _mm256_storeu_pd(s + 4, second_sums);
      _mm_storeu_pd(s + 8, _mm256_castpd256_pd128(third_sums));
      out.count[current] = count_held;
      alignas(32) double l[4], u[4];
      _mm256_store_pd(l, low);
      _mm256_store_pd(u, high);
      out.bounds[current].low = Eigen::Vector3d(l[0], l[1], l[2]);
      out.bounds[current].high = Eigen::Vector3d(u[0], u[1], u[2]);
    }
    current = region;
    if (current < 0) return;
    const double* s = out.sums[current].data();
    first_sums = _mm256_loadu_pd(s);
    second_sums = _mm256_loadu_pd(s + 4);
    third_sums = _mm256_setr_pd(s[8], s[9], 0.0, 0.0);
    count_held = out.count[current];
    const Box3& box = out.bounds[current];
    low = _mm256_setr_pd(box.low.x(), box.low.y(), box.low.z(), 0.0);
    high = _mm256_setr_pd(box.high.x(), box.high.y(), box.high.z(), 0.0);
    list = &out.inliers[current];
  };
  // One pixel's point (x, y, z, 1) joining the held region: its box, and its weighted sums
  // unless it is ambiguous. wt: its weight, DepthNoiseWeight(z).
  auto add_to_box = [&](__m256d p) {
    low = _mm256_min_pd(p, low);
    high = _mm256_max_pd(p, high);
  };
  auto add_to_sums = [&](__m256d p, __m256d wt) {
    const __m256d weighted = _mm256_mul_pd(wt, _mm256_permute4x64_pd(p, _MM_SHUFFLE(2, 1, 0, 3)));  // w (1, x, y, z)
    first_sums = _mm256_add_pd(first_sums, weighted);
    second_sums = _mm256_add_pd(second_sums, _mm256_mul_pd(_mm256_permute4x64_pd(weighted, _MM_SHUFFLE(2, 1, 1, 1)),
                                                           _mm256_permute4x64_pd(p, _MM_SHUFFLE(1, 2, 1, 0))));
    third_sums = _mm256_add_pd(third_sums, _mm256_mul_pd(_mm256_permute4x64_pd(weighted, _MM_SHUFFLE(3, 3, 3, 2)),
                                                         _mm256_permute4x64_pd(p, _MM_SHUFFLE(2, 2, 2, 2))));
    count_held += 1;
  };
  auto point_at = [&](const pcl::PointXYZRGB& q) {
    return _mm256_blend_pd(_mm256_cvtps_pd(_mm_loadu_ps(q.data)), one, 0b1000);
  };
  const double inlier_base = grid.inlier_base, inlier_quadratic = grid.inlier_quadratic;
  const __m256d base4 = _mm256_set1_pd(inlier_base), quadratic4 = _mm256_set1_pd(inlier_quadratic);
  const AssignCandidate* const candidates = grid.candidates;
  const int* const first = grid.first;
  for (int v = 0; v < h; ++v) {
    const int cell_row = (v / cs) * cw;
    const std::uint8_t* usable_row = grid.usable + static_cast<size_t>(v) * w;
    const pcl::PointXYZRGB* point_row = grid.points + static_cast<size_t>(v) * w;
    for (int cx = 0; cx < cw; ++cx) {
      const AssignCandidate* candidate = candidates + first[cell_row + cx];
      const int count = first[cell_row + cx + 1] - first[cell_row + cx];
      if (count == 0) continue;
      // Pixel u as in the scalar loop.
      auto one_pixel = [&](int u) {
        if (!usable_row[u]) return;
        const pcl::PointXYZRGB& p = point_row[u];
        const double x = p.x, y = p.y, z = p.z;
        const double limit = GrowsWithDepth(inlier_base, inlier_quadratic, z);
        int close_planes = 0;
        const int best_region = Nearest(candidate, count, x, y, z, limit, &close_planes);
        if (best_region < 0) return;
        if (best_region != current) hold(best_region);
        list->push_back(v * w + u);
        const __m256d q = point_at(p);
        add_to_box(q);
        if (close_planes > 1) {
          out.ambiguous[v * w + u] = 1;
          return;
        }
        add_to_sums(q, _mm256_set1_pd(DepthNoiseWeight(z)));
      };
      int u = cx * cs;
      const int u_end = std::min(w, u + cs);
      if (count == 1) {
        const AssignCandidate& f = candidate[0];
        const __m256d nx = _mm256_set1_pd(f.nx), ny = _mm256_set1_pd(f.ny), nz = _mm256_set1_pd(f.nz), d = _mm256_set1_pd(f.d);
        for (; u + 4 <= u_end; u += 4) {
          std::uint32_t four;
          std::memcpy(&four, usable_row + u, 4);
          if (four == 0) continue;  // none usable
          if (four == 0x01010101u) {
            const __m256d p0 = point_at(point_row[u]), p1 = point_at(point_row[u + 1]);
            const __m256d p2 = point_at(point_row[u + 2]), p3 = point_at(point_row[u + 3]);
            const __m256d t0 = _mm256_unpacklo_pd(p0, p1), t1 = _mm256_unpackhi_pd(p0, p1);  // x0 x1 z0 z1, y0 y1 . .
            const __m256d t2 = _mm256_unpacklo_pd(p2, p3), t3 = _mm256_unpackhi_pd(p2, p3);
            const __m256d x = _mm256_permute2f128_pd(t0, t2, 0x20), z = _mm256_permute2f128_pd(t0, t2, 0x31);
            const __m256d y = _mm256_permute2f128_pd(t1, t3, 0x20);
            // |nx x + ny y + nz z + d| < base + quadratic z z, each in the scalar loop's order.
            const __m256d distance = _mm256_andnot_pd(
                sign, _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(nx, x), _mm256_mul_pd(ny, y)), _mm256_mul_pd(nz, z)), d));
            const __m256d limit = _mm256_add_pd(base4, _mm256_mul_pd(_mm256_mul_pd(quadratic4, z), z));
            if (_mm256_movemask_pd(_mm256_cmp_pd(distance, limit, _CMP_LT_OQ)) == 0xF) {  // all four join f
              if (f.region != current) hold(f.region);
              const int i = v * w + u;
              list->push_back(i);
              list->push_back(i + 1);
              list->push_back(i + 2);
              list->push_back(i + 3);
              const __m256d wt = _mm256_div_pd(one, _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(z, z), z), z));  // 1 / z^4
              add_to_box(p0);
              add_to_sums(p0, _mm256_permute4x64_pd(wt, _MM_SHUFFLE(0, 0, 0, 0)));
              add_to_box(p1);
              add_to_sums(p1, _mm256_permute4x64_pd(wt, _MM_SHUFFLE(1, 1, 1, 1)));
              add_to_box(p2);
              add_to_sums(p2, _mm256_permute4x64_pd(wt, _MM_SHUFFLE(2, 2, 2, 2)));
              add_to_box(p3);
              add_to_sums(p3, _mm256_permute4x64_pd(wt, _MM_SHUFFLE(3, 3, 3, 3)));
              continue;
            }
          }
          for (int k = 0; k < 4; ++k) one_pixel(u + k);
        }
      }
      for (; u < u_end; ++u) one_pixel(u);
    }
  }
  hold(-1);
}
#pragma GCC pop_options
#else
void AssignPixelsAvx2(const AssignGrid& grid, const AssignOutput& out) { AssignPixelsScalar(grid, out); }
#endif

void AssignPixels(const AssignGrid& grid, const AssignOutput& out) {
  if (AssignPixelsHasAvx2()) {
    AssignPixelsAvx2(grid, out);
  } else {
    AssignPixelsScalar(grid, out);
  }
}

}  // namespace planemap
