#pragma once
// What the robot is sent to fetch: a class, and optionally the object's size. The paper's robot
// grasps the one box in view; with two graspable boxes in a room (a crate before the parcel) the
// class alone cannot tell them apart, and a task says which by its size ("the 24 x 21 x 33 cm
// box"). The size only tells objects apart: the estimate is measured as always.
#include <optional>
#include <string>

#include <Eigen/Core>

#include "planemap/core/plane_map.h"

namespace planemap::nav {

struct TargetDescription {
  std::string label = "box";              // the class (configs/patterns.yaml)
  std::optional<Eigen::Vector3d> size;    // the two horizontal extents (either order), the height [m]
  double tolerance = 0.05;                // a measured dimension this far from the told one is another object's [m]
};

// Why a mapped object cannot be the target's size, or empty when it can: each dimension the map
// measured whole within `tolerance` of the told one, and each it only bounded from below (a face
// cut by the image, a top unseen) not past it by more than `tolerance`. The horizontal extents
// are compared in either order. Always empty without a size.
std::string SizeConflict(const MapObject& object, const TargetDescription& target);

// Whether the map's measurements rule the object out: another class (not unknown) with its height
// measured (a class told apart by height, a box from a locker, is not decided while the top is
// unseen), or a size conflict.
bool RuledOut(const MapObject& object, const TargetDescription& target);

}  // namespace planemap::nav
