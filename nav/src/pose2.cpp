#include "planemap/nav/pose2.h"

#include <cmath>

namespace planemap::nav {

double WrapAngle(double a) {
  a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

Pose2 Compose(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, WrapAngle(a.theta + b.theta)};
}

Pose2 Inverse(const Pose2& a) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return {-(c * a.x + s * a.y), -(-s * a.x + c * a.y), WrapAngle(-a.theta)};
}

Pose2 Between(const Pose2& a, const Pose2& b) { return Compose(Inverse(a), b); }

Pose2 BaseFromCamera(const Pose3& T_world_camera, double camera_forward_offset) {
  const Eigen::Vector3d axis = T_world_camera.linear().col(2);  // optical axis in the world
  const double theta = std::atan2(axis.y(), axis.x());
  const Eigen::Vector3d p = T_world_camera.translation();
  return {p.x() - camera_forward_offset * std::cos(theta), p.y() - camera_forward_offset * std::sin(theta), theta};
}

Pose3 ToPose3(const Pose2& p) { return MakePoseRpy(0.0, 0.0, p.theta, Eigen::Vector3d(p.x, p.y, 0.0)); }

}  // namespace planemap::nav
