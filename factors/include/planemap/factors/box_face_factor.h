#pragma once
// Box face: an observed plane that belongs to a box's face is the face implied by the box's pose
// and its three dimensions.
//
// Box pose T_W_O (axes along its edges, origin at its centre) and dimensions s = (s_x, s_y, s_z).
// Face (axis k, side sigma = +-1) has the outward normal n_W = R_O (sigma e_k) and passes through
// t_O + R_O (sigma s_k / 2 e_k), so with n . x + d = 0:
//   d_W = -n_W . t_O - s_k / 2.
// Outward is toward a camera that sees the face, as the frontend orients planes. That plane is
// then compared with the observation exactly as a landmark is (PlaneObservationFactor: moved into
// the camera frame, minimal 3-row residual, whitened by the observation's covariance). The
// dimensions stay positive through bounds on their block in the problem
// (Problem::SetParameterLowerBound), not through this factor.
#include <ceres/autodiff_cost_function.h>

#include "planemap/factors/plane_observation_factor.h"

namespace planemap {

class BoxFaceFactor {
 public:
  // axis: 0, 1, 2 (the box's x, y, z); side: +1 or -1.
  // min_std: as PlaneObservationFactor's.
  BoxFaceFactor(int axis, int side, const Plane& observed, const Eigen::Matrix4d& covariance, double min_std)
      : axis_(axis), side_(side > 0 ? 1.0 : -1.0), observation_(observed, covariance, min_std) {}

  // camera: T_W_C, box: T_W_O, both [qx qy qz qw tx ty tz]; dimensions: [s_x s_y s_z] [m].
  template <typename T>
  bool operator()(const T* const camera, const T* const box, const T* const dimensions, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_O(box);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_O(box + 4);
    Eigen::Matrix<T, 3, 1> local = Eigen::Matrix<T, 3, 1>::Zero();
    local[axis_] = T(side_);
    const Eigen::Matrix<T, 3, 1> n_W = q_O * local;
    const T d_W = -n_W.dot(t_O) - T(0.5) * dimensions[axis_];
    observation_.Residual(camera, n_W, d_W, residual);
    return true;
  }

  static ceres::CostFunction* Create(int axis, int side, const Plane& observed, const Eigen::Matrix4d& covariance,
                                     double min_std) {
    return new ceres::AutoDiffCostFunction<BoxFaceFactor, 3, 7, 7, 3>(
        new BoxFaceFactor(axis, side, observed, covariance, min_std));
  }

 private:
  const int axis_;
  const double side_;
  const PlaneObservationFactor observation_;
};

}  // namespace planemap
