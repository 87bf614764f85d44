#pragma once
// An infinite plane n.x + d = 0 with unit normal n (DESIGN.md conventions).
#include <cmath>
#include <optional>

#include <Eigen/Core>

#include "planemap/core/pose.h"

namespace planemap {

struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit normal
  double offset = 0.0;                                // d [m]

  // Plane through `point` with normal `normal` (normalised here).
  static Plane FromPointNormal(const Eigen::Vector3d& point, const Eigen::Vector3d& normal);

  // Signed distance of x to the plane [m], positive on the side the normal points to.
  double SignedDistance(const Eigen::Vector3d& x) const { return normal.dot(x) + offset; }

  // The same plane with normal and offset negated.
  Plane Flipped() const { return {-normal, -offset}; }

  // The closest point of the plane to the origin of its frame.
  Eigen::Vector3d ClosestPointToOrigin() const { return -offset * normal; }

  // Ray parameter t >= 0 with n.(origin + t dir) + d = 0, or nothing when the ray is parallel to
  // the plane (|n.dir| below `parallel_eps`) or the hit lies behind the origin.
  // Inline: the renderer calls it for every pixel of every wall.
  std::optional<double> IntersectRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                     double parallel_eps = 1e-12) const {
    const double denom = normal.dot(dir);
    if (std::abs(denom) < parallel_eps) return std::nullopt;
    const double t = -SignedDistance(origin) / denom;
    if (t < 0.0) return std::nullopt;
    return t;
  }
};

// Moves a plane given in frame b into frame a: n_a = R_a_b n_b, d_a = d_b - n_a . t_a_b.
Plane TransformPlane(const Pose3& T_a_b, const Plane& plane_b);

// Angle between the normals of two planes [rad], in [0, pi].
double NormalAngle(const Plane& a, const Plane& b);

// Singular values (ascending) of the matrix whose rows are unit normals, from the sum of their
// outer products n n^T: below a threshold the smallest says the normals do not span 3-D (they fix
// fewer than 3 translation directions), the middle one too that they are all parallel.
Eigen::Vector3d NormalSingularValues(const Eigen::Matrix3d& sum_of_outer_products);

}  // namespace planemap
