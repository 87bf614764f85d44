#pragma once
#include <optional>
#include <string>

#include "planemap/core/image.h"
#include "planemap/core/pose.h"

namespace planemap {

// One registered colour + depth pair. Depth is in metres in the colour camera's optical frame,
// pixel for pixel with the colour image; 0 marks a pixel without measurement.
struct RgbdFrame {
  int index = 0;             // position in its sequence
  double stamp = 0.0;        // depth timestamp [s]; geometry comes from depth
  double color_stamp = 0.0;  // colour timestamp [s]
  ColorImage color;
  DepthImage depth;
  std::optional<Pose3> T_world_camera;  // ground truth, when the sequence has it
};

}  // namespace planemap
