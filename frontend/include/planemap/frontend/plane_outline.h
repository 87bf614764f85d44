#pragma once
// A map plane's outline, for display (HTML reports): the landmark's voxel points projected onto
// its plane, and their convex hull. A face of a box is its outline; a floor or a wall with
// objects in front is covered whole, holes and notches included.
#include <Eigen/Core>
#include <vector>

#include "planemap/core/plane_map.h"

namespace planemap {

// The convex hull of the landmark's points on its plane, counter-clockwise about the normal,
// world [m]; empty when it has fewer than 3 points or they lie on one line.
std::vector<Eigen::Vector3d> PlaneOutline(const PlaneLandmark& landmark);

}  // namespace planemap
