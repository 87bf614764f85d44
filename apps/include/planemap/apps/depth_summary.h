#pragma once
// What the depth of a run of frames looks like, for the commands' summaries.
#include <algorithm>

#include "planemap/core/image.h"

namespace planemap {

struct DepthSummary {
  int frames = 0;
  double valid_fraction_sum = 0.0;
  double z_min = 1e9, z_max = 0.0;  // [m]

  void Add(const DepthImage& depth) {
    size_t valid = 0;
    for (float z : depth.pixels()) {
      if (!IsValidDepth(z)) continue;
      ++valid;
      z_min = std::min<double>(z_min, z);
      z_max = std::max<double>(z_max, z);
    }
    valid_fraction_sum += static_cast<double>(valid) / depth.size();
    ++frames;
  }
  double MeanValidPercent() const { return frames > 0 ? 100.0 * valid_fraction_sum / frames : 0.0; }
};

}  // namespace planemap
