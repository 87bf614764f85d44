#pragma once
// Object centre: the centre the frontend measured in one frame (eq. 7, the mean over the object's
// trihedral angles, camera frame) against the centre of the box, T_W_O's translation.
//   e = (R_W_C c_C + t_W_C - t_O) / sigma   (3 rows)
// It places a box along the axes where no face of it was seen (the edges measure its size, not
// where it is).
#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace planemap {

class ObjectCenterFactor {
 public:
  // center: the observed centre in the camera frame [m]; sigma: its standard deviation [m].
  ObjectCenterFactor(const Eigen::Vector3d& center, double sigma) : center_(center), inverse_sigma_(1.0 / sigma) {}

  // camera: T_W_C, box: T_W_O, both [qx qy qz qw tx ty tz].
  template <typename T>
  bool operator()(const T* const camera, const T* const box, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_C(camera);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_C(camera + 4), t_O(box + 4);
    const Eigen::Matrix<T, 3, 1> e = q_C * center_.cast<T>() + t_C - t_O;
    for (int i = 0; i < 3; ++i) residual[i] = e[i] * T(inverse_sigma_);
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& center, double sigma) {
    return new ceres::AutoDiffCostFunction<ObjectCenterFactor, 3, 7, 7>(new ObjectCenterFactor(center, sigma));
  }

 private:
  const Eigen::Vector3d center_;
  const double inverse_sigma_;
};

}  // namespace planemap
