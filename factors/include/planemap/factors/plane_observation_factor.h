#pragma once
// Plane observation: a landmark plane, moved into the camera frame by the camera's pose, against
// the plane the frontend observed there, weighted by the observation's covariance.
//
// Landmark pi_W = (n_W, d_W) in the world; pose T_W_C = (R, t). In the camera (DESIGN.md:
// d_W = d_C - n_W . t):
//   n_C = R^T n_W,   d_C = d_W + n_W . t.
// The observed plane pi_o = (n_o, d_o) has covariance C (4x4 over (n, d), rank 3: its normal part
// lives in the tangent plane of n_o). The minimal residual is
//   e = [ B^T (n_C - n_o) ;  d_C - d_o ]   (3 rows),
// B (3x2) an orthonormal basis of the plane orthogonal to n_o; e = 0 when the landmark moved by the
// pose is the observed plane. To first order e = J (pi_C - pi_o) with J = diag(B^T, 1), so
// Cov(e) = J C J^T = Sigma, and the factor returns the whitened residual L e with L^T L = Sigma^-1:
// its squared norm is chi-square with 3 degrees of freedom when C is the observation's true
// covariance.
#include <algorithm>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <ceres/autodiff_cost_function.h>

#include "planemap/core/plane.h"

namespace planemap {

// A floor on a plane observation's covariance, applied where the plane was seen: a tilt of
// sigma_normal [rad] about the inliers' centroid c and a shift of sigma_offset [m] along the normal
// there. In (n, d) that is delta d = -delta n . c + delta d_c, so a far plane's small tilt moves its
// offset at the camera a lot, and the floor keeps that correlation (a floor added to (n, d)
// directly would let a far plane's offset and tilt err independently). Returns covariance + floor.
inline Eigen::Matrix4d FlooredPlaneCovariance(const Plane& observed, const Eigen::Vector3d& centroid,
                                              const Eigen::Matrix4d& covariance, double sigma_normal, double sigma_offset) {
  const Eigen::Vector3d n = observed.normal.normalized();
  const Eigen::Vector3d a = n.unitOrthogonal(), b = n.cross(a);
  // Columns: (n, d) per unit tilt about a, about b, and per unit shift, all at the centroid.
  Eigen::Matrix<double, 4, 3> J = Eigen::Matrix<double, 4, 3>::Zero();
  J.block<3, 1>(0, 0) = a;
  J.block<3, 1>(0, 1) = b;
  J(3, 0) = -a.dot(centroid);
  J(3, 1) = -b.dot(centroid);
  J(3, 2) = 1.0;
  const Eigen::Vector3d floor(sigma_normal * sigma_normal, sigma_normal * sigma_normal, sigma_offset * sigma_offset);
  return covariance + J * floor.asDiagonal() * J.transpose();
}

class PlaneObservationFactor {
 public:
  // `min_std` floors the residual's standard deviations (rad for the normal rows, m for the
  // offset): a plane fit from thousands of points can claim a precision the model cannot hold.
  // (The back end floors the covariance about the plane's centroid instead,
  // FlooredPlaneCovariance, and passes 0.)
  PlaneObservationFactor(const Plane& observed, const Eigen::Matrix4d& covariance, double min_std)
      : normal_(observed.normal.normalized()), offset_(observed.offset) {
    const Eigen::Vector3d a = normal_.unitOrthogonal();
    basis_.col(0) = a;
    basis_.col(1) = normal_.cross(a);
    Eigen::Matrix<double, 3, 4> J = Eigen::Matrix<double, 3, 4>::Zero();
    J.block<2, 3>(0, 0) = basis_.transpose();
    J(2, 3) = 1.0;
    Eigen::Matrix3d sigma = J * covariance * J.transpose();
    sigma += std::max(min_std, 0.0) * std::max(min_std, 0.0) * Eigen::Matrix3d::Identity();
    // L with L^T L = Sigma^-1 (so |L e|^2 = e^T Sigma^-1 e), lower triangular: its first two rows
    // whiten the tilt alone (L's top-left block A has A^T A = Sigma_tilt^-1) and the third the
    // offset given the tilt, which for a plane fit, whose tilt and offset are independent at the
    // inliers' centroid, is the shift there. Any such L gives the same cost; this one lets the
    // back end read a block's rows as tilt and shift (backend/src/noise_estimation.h). It is the
    // upper Cholesky factor of Sigma^-1 with the rows and columns in reverse order.
    const Eigen::Matrix3d reverse = Eigen::Matrix3d::Identity().rowwise().reverse();
    const Eigen::Matrix3d upper = Eigen::LLT<Eigen::Matrix3d>(reverse * sigma.inverse() * reverse).matrixU();
    sqrt_information_ = reverse * upper * reverse;
  }

  // pose: [qx qy qz qw tx ty tz] (T_W_C); plane: [nx ny nz d] (world).
  template <typename T>
  bool operator()(const T* const pose, const T* const plane, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> n_W(plane);
    Residual(pose, Eigen::Matrix<T, 3, 1>(n_W), plane[3], residual);
    return true;
  }

  // The whitened residual of the world plane (n_W, d_W) seen from the camera at `pose`; other
  // factors that imply a plane (a box's face) share it.
  template <typename T>
  void Residual(const T* const pose, const Eigen::Matrix<T, 3, 1>& n_W, const T& d_W, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(pose);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(pose + 4);
    const Eigen::Matrix<T, 3, 1> n_C = q.conjugate() * n_W;
    const T d_C = d_W + n_W.dot(t);
    Eigen::Matrix<T, 3, 1> e;
    e.template head<2>() = basis_.transpose().cast<T>() * (n_C - normal_.cast<T>());
    e[2] = d_C - T(offset_);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residual);
    whitened = sqrt_information_.cast<T>() * e;
  }

  static ceres::CostFunction* Create(const Plane& observed, const Eigen::Matrix4d& covariance, double min_std) {
    return new ceres::AutoDiffCostFunction<PlaneObservationFactor, 3, 7, 4>(
        new PlaneObservationFactor(observed, covariance, min_std));
  }

  const Eigen::Matrix3d& sqrt_information() const { return sqrt_information_; }

 private:
  const Eigen::Vector3d normal_;
  const double offset_;
  Eigen::Matrix<double, 3, 2> basis_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace planemap
