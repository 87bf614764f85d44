#include "planemap/frontend/silhouette.h"

#include <cstdint>

namespace planemap {

std::vector<int> SilhouettePixels(const Cloud& cloud, const std::vector<int>& inliers, double min_gap,
                                  int max_missing) {
  const int width = static_cast<int>(cloud.width), height = static_cast<int>(cloud.height);
  std::vector<std::uint8_t> own(static_cast<size_t>(width) * height, 0);
  for (int i : inliers) own[i] = 1;
  static constexpr int kSteps[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  std::vector<int> pixels;
  for (int i : inliers) {
    const int u = i % width, v = i / width;
    const float z = cloud[i].z;
    bool background = false, blocked = false;
    for (const auto& step : kSteps) {
      int m = 1;
      // The first pixel with depth in this direction, past at most max_missing without.
      for (; m <= max_missing + 1; ++m) {
        const int x = u + m * step[0], y = v + m * step[1];
        if (x < 0 || y < 0 || x >= width || y >= height) {
          m = max_missing + 2;  // off the image: unknown
          break;
        }
        if (IsValidPoint(cloud[y * width + x])) break;
      }
      if (m > max_missing + 1) {  // off the image, or a hole: the surface may go on
        blocked = true;
        break;
      }
      const int n = (v + m * step[1]) * width + (u + m * step[0]);
      if (own[n]) continue;  // the surface goes on this way
      if (cloud[n].z < z + min_gap) {
        blocked = true;
        break;
      }
      background = true;
    }
    if (background && !blocked) pixels.push_back(i);
  }
  return pixels;
}

}  // namespace planemap
