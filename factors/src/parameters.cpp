#include "planemap/factors/parameters.h"

#include <Eigen/Geometry>

namespace planemap {

PoseBlock ToBlock(const Pose3& T) {
  const Eigen::Quaterniond q(T.linear());
  const Eigen::Vector3d& t = T.translation();
  return {q.x(), q.y(), q.z(), q.w(), t.x(), t.y(), t.z()};
}

Pose3 PoseFromBlock(const double* block) {
  const Eigen::Quaterniond q(block[3], block[0], block[1], block[2]);
  return MakePose(q.normalized(), Eigen::Vector3d(block[4], block[5], block[6]));
}

PlaneBlock ToBlock(const Plane& plane) { return {plane.normal.x(), plane.normal.y(), plane.normal.z(), plane.offset}; }

Plane PlaneFromBlock(const double* block) {
  return Plane{Eigen::Vector3d(block[0], block[1], block[2]).normalized(), block[3]};
}

}  // namespace planemap
