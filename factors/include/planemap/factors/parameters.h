#pragma once
// The back end's variables as Ceres parameter blocks, and the manifolds they live on.
//   pose  T_W_C: [qx qy qz qw tx ty tz], a unit quaternion (Eigen's order) and a translation [m]:
//                EigenQuaternionManifold x EuclideanManifold<3>, 6 degrees of freedom;
//   plane (n, d) with n . x + d = 0: [nx ny nz d], a unit normal and an offset [m]:
//                SphereManifold<3> x EuclideanManifold<1>, the minimal 3 degrees of freedom of
//                a plane (as GTSAM's OrientedPlane3).
#include <array>

#include <ceres/manifold.h>
#include <ceres/product_manifold.h>
#include <ceres/sphere_manifold.h>

#include "planemap/core/plane.h"
#include "planemap/core/pose.h"

namespace planemap {

using PoseManifold = ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>;
using PlaneManifold = ceres::ProductManifold<ceres::SphereManifold<3>, ceres::EuclideanManifold<1>>;

using PoseBlock = std::array<double, 7>;
using PlaneBlock = std::array<double, 4>;

PoseBlock ToBlock(const Pose3& T);
Pose3 PoseFromBlock(const double* block);
PlaneBlock ToBlock(const Plane& plane);
Plane PlaneFromBlock(const double* block);  // the normal renormalised

}  // namespace planemap
