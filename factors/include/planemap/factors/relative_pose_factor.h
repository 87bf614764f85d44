#pragma once
// Relative pose between two keyframes, as tracking measured it, and a prior on one pose (the
// gauge: plane observations fix poses only relative to the landmarks, which move with them).
//
// Poses T_W_A, T_W_B and a measured T_A_B (rotation q_m, translation t_m). The prediction is
// T_A_B^ = T_W_A^-1 T_W_B: q^ = q_A^* q_B, t^ = q_A^* (t_B - t_A). The residual is the error in
// A's frame, translation first:
//   e = [ t^ - t_m ;  2 vec(q_m^* q^) ]   (6 rows; 2 vec(.) is the rotation vector to first order,
//                                          the quaternion taken with w >= 0)
// whitened by L with L^T L = Sigma^-1, Sigma the measurement's 6x6 covariance (translation
// [m^2], then rotation [rad^2]). The prior is the same residual against a fixed pose: T_W_A the
// identity and T_W_B the variable.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/autodiff_cost_function.h>

#include "planemap/core/pose.h"

namespace planemap {

namespace internal {
// e = [t^ - t_m; 2 vec(q_m^* q^)] for the predicted (q^, t^) against the measured (q_m, t_m).
template <typename T>
Eigen::Matrix<T, 6, 1> PoseError(const Eigen::Quaternion<T>& q_hat, const Eigen::Matrix<T, 3, 1>& t_hat,
                                 const Eigen::Quaterniond& q_m, const Eigen::Vector3d& t_m) {
  Eigen::Quaternion<T> dq = q_m.template cast<T>().conjugate() * q_hat;
  if (dq.w() < T(0.0)) dq.coeffs() = -dq.coeffs();  // q and -q are one rotation: take the short way
  Eigen::Matrix<T, 6, 1> e;
  e.template head<3>() = t_hat - t_m.template cast<T>();
  e.template tail<3>() = T(2.0) * dq.vec();
  return e;
}
}  // namespace internal

class RelativePoseFactor {
 public:
  RelativePoseFactor(const Pose3& T_A_B, const Eigen::Matrix<double, 6, 6>& sqrt_information)
      : q_m_(T_A_B.linear()), t_m_(T_A_B.translation()), sqrt_information_(sqrt_information) {}

  // pose_a, pose_b: [qx qy qz qw tx ty tz] (T_W_A, T_W_B).
  template <typename T>
  bool operator()(const T* const pose_a, const T* const pose_b, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_a(pose_a), q_b(pose_b);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_a(pose_a + 4), t_b(pose_b + 4);
    const Eigen::Quaternion<T> q_a_inverse = q_a.conjugate();
    const Eigen::Matrix<T, 6, 1> e = internal::PoseError<T>(q_a_inverse * q_b, q_a_inverse * (t_b - t_a), q_m_, t_m_);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> whitened(residual);
    whitened = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(const Pose3& T_A_B, const Eigen::Matrix<double, 6, 6>& sqrt_information) {
    return new ceres::AutoDiffCostFunction<RelativePoseFactor, 6, 7, 7>(new RelativePoseFactor(T_A_B, sqrt_information));
  }

 private:
  const Eigen::Quaterniond q_m_;
  const Eigen::Vector3d t_m_;
  const Eigen::Matrix<double, 6, 6> sqrt_information_;
};

class PosePriorFactor {
 public:
  PosePriorFactor(const Pose3& T_W_B, const Eigen::Matrix<double, 6, 6>& sqrt_information)
      : q_m_(T_W_B.linear()), t_m_(T_W_B.translation()), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const pose, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(pose);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(pose + 4);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> whitened(residual);
    whitened = sqrt_information_.cast<T>() * internal::PoseError<T>(Eigen::Quaternion<T>(q), Eigen::Matrix<T, 3, 1>(t), q_m_, t_m_);
    return true;
  }

  static ceres::CostFunction* Create(const Pose3& T_W_B, const Eigen::Matrix<double, 6, 6>& sqrt_information) {
    return new ceres::AutoDiffCostFunction<PosePriorFactor, 6, 7>(new PosePriorFactor(T_W_B, sqrt_information));
  }

 private:
  const Eigen::Quaterniond q_m_;
  const Eigen::Vector3d t_m_;
  const Eigen::Matrix<double, 6, 6> sqrt_information_;
};

}  // namespace planemap
