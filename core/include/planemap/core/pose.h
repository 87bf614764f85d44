#pragma once
// Rigid transforms. Naming: T_a_b maps coordinates in frame b into frame a, so T_a_b * T_b_c = T_a_c
// and p_a = T_a_b * p_b (DESIGN.md conventions).
#include <Eigen/Geometry>

namespace planemap {

using Pose3 = Eigen::Isometry3d;

// Pose from a (not necessarily normalised) quaternion and a translation [m].
Pose3 MakePose(const Eigen::Quaterniond& q, const Eigen::Vector3d& t);

// Pose from roll, pitch, yaw [rad] (R = Rz(yaw) Ry(pitch) Rx(roll)) and a translation [m].
Pose3 MakePoseRpy(double roll, double pitch, double yaw, const Eigen::Vector3d& t);

// Rotation angle of R [rad], in [0, pi].
double RotationAngle(const Eigen::Matrix3d& R);

// A pose as (rotation vector [rad], translation [m]) and back: rotation and translation apart,
// not the SE(3) exponential (the translation is taken as it is). Motion models and
// Gauss-Newton steps on poses use this parametrisation.
Eigen::Matrix<double, 6, 1> RotationVectorAndTranslation(const Pose3& T);
Pose3 PoseFromRotationVectorAndTranslation(const Eigen::Matrix<double, 6, 1>& xi);

// An axis-aligned box [low, high] (empty as constructed) [m].
struct Box3 {
  Eigen::Vector3d low = Eigen::Vector3d::Constant(1e30), high = Eigen::Vector3d::Constant(-1e30);
  // Whether the two boxes, each grown by margin, intersect.
  bool Overlaps(const Box3& o, double margin) const {
    return ((low.array() - margin) <= o.high.array()).all() && ((o.low.array() - margin) <= high.array()).all();
  }
  bool Empty() const { return (low.array() > high.array()).any(); }
  void Extend(const Eigen::Vector3d& p) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  void Extend(const Box3& o) {
    low = low.cwiseMin(o.low);
    high = high.cwiseMax(o.high);
  }
  // Length of the diagonal; 0 when empty [m].
  double Diagonal() const { return Empty() ? 0.0 : (high - low).norm(); }
};

// The axis-aligned box holding the box [low, high] moved by T: its 8 corners moved, boxed again.
Box3 TransformBox(const Pose3& T, const Eigen::Vector3d& low, const Eigen::Vector3d& high);

// Interpolates between two poses: slerp on rotation, linear on translation; s in [0, 1].
Pose3 Interpolate(const Pose3& T_a, const Pose3& T_b, double s);

// Camera optical frame (x right, y down, z forward) expressed in a REP-103 body frame
// (x forward, y left, z up): R_body_optical.
Eigen::Matrix3d RotationBodyFromOptical();

// A camera (optical frame: z forward, y down) at `eye` looking at `target`, world z up; `target`
// must not be straight above or below `eye`.
Pose3 LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

}  // namespace planemap
