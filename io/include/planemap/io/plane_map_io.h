#pragma once
// A map to and from JSON (world frame, metres): planes with their inlier moments and voxel
// points, edges, objects with class, dimensions, centre, axes, grasp axis and the observations
// behind them, keyframes. What PlaneMapJson writes, ReadPlaneMapJson reads back whole, so maps of
// two runs can be merged later (`planemap merge`).
#include <string>

#include "planemap/core/plane_map.h"

namespace planemap {

std::string PlaneMapJson(const PlaneMap& map, int indent = 2);

// Throws InputError naming the file and the field that is missing or wrong.
PlaneMap ReadPlaneMapJson(const std::string& file);

}  // namespace planemap
