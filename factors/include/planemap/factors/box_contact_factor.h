#pragma once
// Box contact: a box standing on a supporting plane (the floor) has its bottom face on that plane
// and its z axis along the plane's normal. A structure prior the graph supports when the box's
// lowest face is within reach of the floor; optional in the back end.
//
// Box pose T_W_O (z axis up), dimensions s, support plane (n_f, d_f) with n_f up. The bottom
// face's centre is b = t_O - s_z / 2 R_O e_z; the residual is
//   e = [ (R_O e_z) x n_f / sigma_angle ;  (n_f . b + d_f) / sigma_distance ]   (4 rows)
// zero when the box's z axis is the plane's normal and its bottom lies on the plane. The cross
// product has rank 2 on the sphere; its third row carries no extra weight to first order.
#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace planemap {

class BoxContactFactor {
 public:
  // sigma_distance [m], sigma_angle [rad]: how far from exact contact the prior allows.
  BoxContactFactor(double sigma_distance, double sigma_angle)
      : inverse_sigma_distance_(1.0 / sigma_distance), inverse_sigma_angle_(1.0 / sigma_angle) {}

  // box: T_W_O [qx qy qz qw tx ty tz]; dimensions: [s_x s_y s_z] [m]; plane: [nx ny nz d] (world).
  template <typename T>
  bool operator()(const T* const box, const T* const dimensions, const T* const plane, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_O(box);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_O(box + 4);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> n_f(plane);
    const Eigen::Matrix<T, 3, 1> z = q_O * Eigen::Matrix<T, 3, 1>::UnitZ();
    const Eigen::Matrix<T, 3, 1> bottom = t_O - T(0.5) * dimensions[2] * z;
    const Eigen::Matrix<T, 3, 1> tilt = z.cross(n_f);
    for (int i = 0; i < 3; ++i) residual[i] = tilt[i] * T(inverse_sigma_angle_);
    residual[3] = (n_f.dot(bottom) + plane[3]) * T(inverse_sigma_distance_);
    return true;
  }

  static ceres::CostFunction* Create(double sigma_distance, double sigma_angle) {
    return new ceres::AutoDiffCostFunction<BoxContactFactor, 4, 7, 3, 4>(new BoxContactFactor(sigma_distance, sigma_angle));
  }

 private:
  const double inverse_sigma_distance_;
  const double inverse_sigma_angle_;
};

}  // namespace planemap
