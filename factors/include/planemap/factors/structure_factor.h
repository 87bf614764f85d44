#pragma once
// Structure priors between two plane landmarks that the plane graph says meet at a right angle
// (a box's faces, a wall on the floor) or run parallel (a box's opposite faces):
//   perpendicular: e = (n_a . n_b) / sigma                (1 row; sin of the angle's deviation from 90 deg)
//   parallel:      e = (n_a x n_b) / sigma                (3 rows, rank 2; sin of the angle between them,
//                                                         zero for opposite normals too)
// sigma [rad] is how far from exact the structure is believed to be. Optional: the back end adds
// them only when the config asks.
#include <ceres/autodiff_cost_function.h>
#include <Eigen/Core>

namespace planemap {

class PerpendicularPlanesFactor {
 public:
  explicit PerpendicularPlanesFactor(double sigma) : inverse_sigma_(1.0 / sigma) {}

  // plane_a, plane_b: [nx ny nz d] (world).
  template <typename T>
  bool operator()(const T* const plane_a, const T* const plane_b, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> n_a(plane_a), n_b(plane_b);
    residual[0] = n_a.dot(n_b) * T(inverse_sigma_);
    return true;
  }

  static ceres::CostFunction* Create(double sigma) {
    return new ceres::AutoDiffCostFunction<PerpendicularPlanesFactor, 1, 4, 4>(new PerpendicularPlanesFactor(sigma));
  }

 private:
  const double inverse_sigma_;
};

class ParallelPlanesFactor {
 public:
  explicit ParallelPlanesFactor(double sigma) : inverse_sigma_(1.0 / sigma) {}

  template <typename T>
  bool operator()(const T* const plane_a, const T* const plane_b, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> n_a(plane_a), n_b(plane_b);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residual);
    whitened = n_a.cross(n_b) * T(inverse_sigma_);
    return true;
  }

  static ceres::CostFunction* Create(double sigma) {
    return new ceres::AutoDiffCostFunction<ParallelPlanesFactor, 3, 4, 4>(new ParallelPlanesFactor(sigma));
  }

 private:
  const double inverse_sigma_;
};

}  // namespace planemap
