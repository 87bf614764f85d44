// Compiled without GCC's SLP vectorizer (frontend/CMakeLists.txt). Its cost model turned these
// ten scalar sums into vector shuffles through the stack whenever an unrelated edit to the
// segmenter's file tipped it (the segmenter's cell pass went from 276 to 391 million
// instructions over the benchmark's frames): alone in this file, and with that pass off, the
// sums stay in ten registers, one scalar addition each.
#include "cell_sums.h"

#include <cmath>
#include <cstddef>

namespace planemap {

CellSums SumCell(const pcl::PointXYZRGB* points, const std::uint8_t* usable, int w, int u0, int u1, int v0, int v1,
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

}  // namespace planemap
