#pragma once
// A robot base pose on the floor: position (x, y) and heading theta, in the world frame W
// (z up, DESIGN.md). The base frame B is REP 103: x forward, y left.
#include <Eigen/Core>

#include "planemap/core/pose.h"

namespace planemap::nav {

struct Pose2 {
  double x = 0.0, y = 0.0;  // [m]
  double theta = 0.0;       // heading, counter-clockwise from world x [rad]

  Eigen::Vector2d Position() const { return {x, y}; }
};

// Angle wrapped into (-pi, pi].
double WrapAngle(double a);

// a * b: b expressed in a's frame, moved into a's parent frame.
Pose2 Compose(const Pose2& a, const Pose2& b);
// The inverse transform of a.
Pose2 Inverse(const Pose2& a);
// b seen from a: Inverse(a) * b. A relative motion (dx forward, dy left, dtheta) from a to b.
Pose2 Between(const Pose2& a, const Pose2& b);

// The base pose under a camera: the camera's position dropped to the floor, moved back by the
// camera's forward offset on the head, and the heading of its optical axis (z) projected on the
// floor. Roll, pitch and head sway do not change it.
Pose2 BaseFromCamera(const Pose3& T_world_camera, double camera_forward_offset);

// The 3-D base pose (on the floor, z = 0) of a Pose2.
Pose3 ToPose3(const Pose2& p);

}  // namespace planemap::nav
