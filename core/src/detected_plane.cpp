#include "planemap/core/detected_plane.h"

#include <cmath>

#include <Eigen/Eigenvalues>

namespace planemap {

PlaneFit FitPlane(const PointMoments& m) {
  PlaneFit fit;
  if (m.n < 3.0) return fit;
  const Eigen::Vector3d mean = m.Mean();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m.Covariance());
  const Eigen::Vector3d eigenvalues = eig.eigenvalues();  // ascending
  if (!(eigenvalues(1) > 1e-12)) return fit;              // collinear or coincident points
  Eigen::Vector3d n = eig.eigenvectors().col(0);
  double d = -n.dot(mean);
  if (d < 0.0) {  // orient toward the origin (the camera)
    n = -n;
    d = -d;
  }
  fit.plane = {n, d};
  fit.centroid = mean;
  const double variance = std::max(eigenvalues(0), 0.0);  // weighted mean squared residual
  fit.rms = std::sqrt(variance);
  // Covariance of (n, d): Gauss-Newton information sum w [p;1][p;1]^T / s^2 of the residual
  // n.p + d, restricted to the tangent space of |n| = 1 (directions orthogonal to (n, 0)).
  // s^2, the variance of a point of unit weight, is estimated from the residuals:
  // sum w r^2 / (n - 3), floored so a noiseless fit keeps a finite covariance.
  const double sigma2 = std::max(variance * m.w / std::max(m.n - 3.0, 1.0), 1e-12 * m.w / m.n);
  Eigen::Matrix4d information;
  information.topLeftCorner<3, 3>() = m.sum_outer;
  information.topRightCorner<3, 1>() = m.sum;
  information.bottomLeftCorner<1, 3>() = m.sum.transpose();
  information(3, 3) = m.w;
  information /= sigma2;
  // Basis of the tangent space: two directions orthogonal to n (rotating the normal), and d.
  Eigen::Matrix<double, 4, 3> basis = Eigen::Matrix<double, 4, 3>::Zero();
  const Eigen::Vector3d a = n.unitOrthogonal(), b = n.cross(a);
  basis.block<3, 1>(0, 0) = a;
  basis.block<3, 1>(0, 1) = b;
  basis(3, 2) = 1.0;
  const Eigen::Matrix3d reduced = basis.transpose() * information * basis;
  fit.covariance = basis * reduced.inverse() * basis.transpose();
  fit.ok = true;
  return fit;
}

}  // namespace planemap
