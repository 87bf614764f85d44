#include "planemap/core/plane.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "planemap/core/pose.h"

namespace planemap {

Plane Plane::FromPointNormal(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n = normal.normalized();
  return {n, -n.dot(point)};
}

Plane TransformPlane(const Pose3& T_a_b, const Plane& plane_b) {
  const Eigen::Vector3d n_a = T_a_b.linear() * plane_b.normal;
  return {n_a, plane_b.offset - n_a.dot(T_a_b.translation())};
}

double NormalAngle(const Plane& a, const Plane& b) {
  return std::atan2(a.normal.cross(b.normal).norm(), a.normal.dot(b.normal));
}

Eigen::Vector3d NormalSingularValues(const Eigen::Matrix3d& sum_of_outer_products) {
  // The singular values of A are the square roots of the eigenvalues (ascending) of A^T A.
  const Eigen::Vector3d eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(sum_of_outer_products).eigenvalues();
  return eigenvalues.cwiseMax(0.0).cwiseSqrt();
}

}  // namespace planemap
