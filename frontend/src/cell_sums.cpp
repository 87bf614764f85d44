// Compiled without GCC's SLP vectorizer (frontend/CMakeLists.txt). Its cost model turned these
// ten scalar sums into vector shuffles through the stack whenever an unrelated edit to the
// segmenter's file tipped it (the segmenter's cell pass went from 276 to 391 million
// instructions over the benchmark's frames): alone in this file, and with that pass off, the
// sums stay in ten registers, one scalar addition each. Where the processor has AVX2 the sums
// go three vectors at a time instead (SumCellAvx2, chosen at run time: the build targets plain
// x86-64), to the same doubles; -ffp-contract=off keeps products and sums apart in both.
#include "cell_sums.h"

#include <cmath>
#include <cstddef>
#include <cstring>

#include "cpu_features.h"

#ifdef PLANEMAP_AVX2_LOOPS
#include <immintrin.h>
#endif

namespace planemap {

CellSums SumCellScalar(const pcl::PointXYZRGB* points, const std::uint8_t* usable, int w, int u0, int u1, int v0, int v1,
                       float jump_relative) {
  double n = 0, sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
  bool jump = false;
  for (int v = v0; v < v1; ++v) {
    const pcl::PointXYZRGB* row = points + static_cast<std::size_t>(v) * w;
    const std::uint8_t* use = usable + static_cast<std::size_t>(v) * w;
    const bool has_below = v + 1 < v1;
    for (int u = u0; u < u1; ++u) {
      if (!use[u]) continue;
      const float pz = row[u].z;
      const double x = row[u].x, y = row[u].y, z = pz;
      n += 1;
      sx += x; sy += y; sz += z;
      sxx += x * x; sxy += x * y; sxz += x * z; syy += y * y; syz += y * z; szz += z * z;
      const float limit = jump_relative * pz;
      if (u + 1 < u1 && use[u + 1] && std::abs(row[u + 1].z - pz) > limit) jump = true;
      if (has_below && use[u + w] && std::abs(row[u + w].z - pz) > limit) jump = true;
    }
  }
  CellSums s;
  s.n = n, s.sx = sx, s.sy = sy, s.sz = sz, s.sxx = sxx, s.sxy = sxy, s.sxz = sxz, s.syy = syy, s.syz = syz, s.szz = szz;
  s.jump = jump;
  return s;
}

bool SumCellHasAvx2() { return CpuHasAvx2(); }

#ifdef PLANEMAP_AVX2_LOOPS
// The same sums with AVX2, in the same order: the ten sums lie side by side in three vectors, each
// still added to one point after another, so every sum is the same double as SumCellScalar's.
// A point's x, y, z (and PCL's fourth float, replaced by 1: the count) are read as one vector:
//   first  += (x, y, z, 1)                  -> sx, sy, sz, n
//   second += (x, x, x, y) * (x, y, z, y)   -> sxx, sxy, sxz, syy
//   third  += (y, z, 1, 1) * (z, z, 1, 1)   -> syz, szz (the other two lanes unused)
// Products and sums stay separate instructions, as in the scalar loop (the file is compiled with
// -ffp-contract=off). The depth-jump test takes eight pixels at a time, on each row's depths and
// usable bytes copied side by side (zero past the cell's end): the same single-precision
// difference and limit for each pair of usable 4-neighbours as in the scalar loop. Cells wider
// than kMaxRow pixels take the scalar test.
constexpr int kMaxRow = 64;

#pragma GCC push_options
#pragma GCC target("avx2")
static bool JumpInRows(const float* above, const std::uint8_t* above_use, const float* row, const std::uint8_t* use,
                       int n, bool has_above, float jump_relative) {
  const __m256 jr = _mm256_set1_ps(jump_relative), sign = _mm256_set1_ps(-0.0f);
  const __m256i zero = _mm256_setzero_si256();
  auto usable8 = [&](const std::uint8_t* bytes) {  // eight usable bytes as lanes of all ones or zeros
    const __m256i wide = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(bytes)));
    return _mm256_castsi256_ps(_mm256_xor_si256(_mm256_cmpeq_epi32(wide, zero), _mm256_set1_epi32(-1)));
  };
  // |other - z| > jump_relative z, both usable.
  auto apart = [&](__m256 z, __m256 other, __m256 both) {
    const __m256 difference = _mm256_andnot_ps(sign, _mm256_sub_ps(other, z));
    return _mm256_movemask_ps(_mm256_and_ps(_mm256_cmp_ps(difference, _mm256_mul_ps(jr, z), _CMP_GT_OQ), both)) != 0;
  };
  for (int k = 0; k < n; k += 8) {
    const __m256 z = _mm256_loadu_ps(row + k);
    const __m256 here = usable8(use + k);
    if (apart(z, _mm256_loadu_ps(row + k + 1), _mm256_and_ps(here, usable8(use + k + 1)))) return true;
    if (has_above && apart(_mm256_loadu_ps(above + k), z, _mm256_and_ps(usable8(above_use + k), here))) return true;
  }
  return false;
}

CellSums SumCellAvx2(const pcl::PointXYZRGB* points, const std::uint8_t* usable, int w, int u0, int u1, int v0, int v1,
                     float jump_relative) {
  static_assert(sizeof(pcl::PointXYZRGB) == 32 && offsetof(pcl::PointXYZRGB, data) == 0, "x, y, z, pad lead each point");
  const int n = u1 - u0;
  if (n > kMaxRow) return SumCellScalar(points, usable, w, u0, u1, v0, v1, jump_relative);
  const __m256d one = _mm256_set1_pd(1.0);
  __m256d first = _mm256_setzero_pd(), second = _mm256_setzero_pd(), third = _mm256_setzero_pd();
  bool jump = false;
  // This row's and the one above's depths and usable bytes, 0 past the cell's end (the loads
  // read up to 8 on).
  alignas(32) float depth[2][kMaxRow + 16];
  alignas(32) std::uint8_t used[2][kMaxRow + 16];
  for (int r = 0; r < 2; ++r) {
    std::memset(depth[r] + n, 0, 16 * sizeof(float));
    std::memset(used[r] + n, 0, 16);
  }
  for (int v = v0; v < v1; ++v) {
    const pcl::PointXYZRGB* row = points + static_cast<std::size_t>(v) * w;
    const std::uint8_t* use = usable + static_cast<std::size_t>(v) * w;
    float* z_row = depth[v & 1];
    std::uint8_t* use_row = used[v & 1];
    std::memcpy(use_row, use + u0, n);
    for (int u = u0; u < u1; ++u) {
      if (!use[u]) {
        z_row[u - u0] = 0.0f;
        continue;
      }
      const __m256d p = _mm256_blend_pd(_mm256_cvtps_pd(_mm_loadu_ps(row[u].data)), one, 0b1000);  // x, y, z, 1
      first = _mm256_add_pd(first, p);
      const __m256d a = _mm256_permute4x64_pd(p, _MM_SHUFFLE(1, 0, 0, 0));  // x, x, x, y
      const __m256d b = _mm256_permute4x64_pd(p, _MM_SHUFFLE(1, 2, 1, 0));  // x, y, z, y
      second = _mm256_add_pd(second, _mm256_mul_pd(a, b));
      const __m256d c = _mm256_permute4x64_pd(p, _MM_SHUFFLE(3, 3, 2, 1));  // y, z, 1, 1
      const __m256d d = _mm256_permute4x64_pd(p, _MM_SHUFFLE(3, 3, 2, 2));  // z, z, 1, 1
      third = _mm256_add_pd(third, _mm256_mul_pd(c, d));
      z_row[u - u0] = row[u].z;
    }
    if (!jump) {
      jump = JumpInRows(depth[(v & 1) ^ 1], used[(v & 1) ^ 1], z_row, use_row, n, v > v0, jump_relative);
    }
  }
  alignas(32) double f[4], g[4], h[4];
  _mm256_store_pd(f, first);
  _mm256_store_pd(g, second);
  _mm256_store_pd(h, third);
  CellSums s;
  s.sx = f[0], s.sy = f[1], s.sz = f[2], s.n = f[3];
  s.sxx = g[0], s.sxy = g[1], s.sxz = g[2], s.syy = g[3];
  s.syz = h[0], s.szz = h[1];
  s.jump = jump;
  return s;
}
#pragma GCC pop_options
#else
CellSums SumCellAvx2(const pcl::PointXYZRGB* points, const std::uint8_t* usable, int w, int u0, int u1, int v0, int v1,
                     float jump_relative) {
  return SumCellScalar(points, usable, w, u0, u1, v0, v1, jump_relative);
}
#endif

CellSums SumCell(const pcl::PointXYZRGB* points, const std::uint8_t* usable, int w, int u0, int u1, int v0, int v1,
                 float jump_relative) {
  if (SumCellHasAvx2()) return SumCellAvx2(points, usable, w, u0, u1, v0, v1, jump_relative);
  return SumCellScalar(points, usable, w, u0, u1, v0, v1, jump_relative);
}

}  // namespace planemap
