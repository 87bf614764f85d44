#include "planemap/core/pose.h"

#include <algorithm>
#include <cmath>

namespace planemap {

Pose3 MakePose(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
  Pose3 T = Pose3::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = t;
  return T;
}

Pose3 MakePoseRpy(double roll, double pitch, double yaw, const Eigen::Vector3d& t) {
  const Eigen::Quaterniond q = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
  return MakePose(q, t);
}

double RotationAngle(const Eigen::Matrix3d& R) {
  // atan2 form stays accurate near 0 and pi, unlike acos((trace - 1) / 2).
  const Eigen::Vector3d axis_sin(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  return std::atan2(0.5 * axis_sin.norm(), 0.5 * (R.trace() - 1.0));
}

Pose3 Interpolate(const Pose3& T_a, const Pose3& T_b, double s) {
  const Eigen::Quaterniond q_a(T_a.linear());
  const Eigen::Quaterniond q_b(T_b.linear());
  return MakePose(q_a.slerp(s, q_b), (1.0 - s) * T_a.translation() + s * T_b.translation());
}

Eigen::Matrix3d RotationBodyFromOptical() {
  Eigen::Matrix3d R;
  // Columns: optical x (right) = -body y, optical y (down) = -body z, optical z (forward) = body x.
  R << 0, 0, 1,
      -1, 0, 0,
       0, -1, 0;
  return R;
}

Eigen::Matrix<double, 6, 1> RotationVectorAndTranslation(const Pose3& T) {
  const Eigen::AngleAxisd aa(T.linear());
  Eigen::Matrix<double, 6, 1> xi;
  xi << aa.angle() * aa.axis(), T.translation();
  return xi;
}

Pose3 PoseFromRotationVectorAndTranslation(const Eigen::Matrix<double, 6, 1>& xi) {
  Pose3 T = Pose3::Identity();
  const double angle = xi.head<3>().norm();
  if (angle > 0.0) T.linear() = Eigen::AngleAxisd(angle, xi.head<3>() / angle).toRotationMatrix();
  T.translation() = xi.tail<3>();
  return T;
}

Box3 TransformBox(const Pose3& T, const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  Box3 box;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner = T * Eigen::Vector3d((k & 1) ? high.x() : low.x(), (k & 2) ? high.y() : low.y(),
                                                       (k & 4) ? high.z() : low.z());
    box.low = box.low.cwiseMin(corner);
    box.high = box.high.cwiseMax(corner);
  }
  return box;
}

Pose3 LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  Pose3 T = Pose3::Identity();
  T.linear() << x, z.cross(x), z;
  T.translation() = eye;
  return T;
}

}  // namespace planemap
