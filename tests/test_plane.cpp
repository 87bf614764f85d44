// Infinite planes: frame changes, ray intersection, normal angles.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "planemap/core/plane.h"
#include "planemap/core/pose.h"
#include "test_support.h"

namespace planemap {
namespace {

using planemap::testing::PlanesNear;

struct Random {
  explicit Random(unsigned seed) : rng(seed) {}
  Eigen::Vector3d UnitVector() {
    Eigen::Vector3d v;
    do {
      v = Eigen::Vector3d(coef(rng), coef(rng), coef(rng));
    } while (v.norm() < 1e-3);
    return v.normalized();
  }
  Eigen::Vector3d Point(double half_extent) {
    return half_extent * Eigen::Vector3d(coef(rng), coef(rng), coef(rng));
  }
  Pose3 RandomPose(double half_extent) {
    const Eigen::Quaterniond q(coef(rng), coef(rng), coef(rng), coef(rng));
    return MakePose(q, Point(half_extent));
  }
  double Uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

  std::mt19937 rng;
  std::uniform_real_distribution<double> coef{-1.0, 1.0};
};

// Two unit vectors spanning the plane with normal n.
void InPlaneBasis(const Eigen::Vector3d& n, Eigen::Vector3d* e1, Eigen::Vector3d* e2) {
  const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  *e1 = n.cross(helper).normalized();
  *e2 = n.cross(*e1);
}

TEST(TransformPlane, PointsOnThePlaneStayOnIt) {
  Random random(42);
  for (int trial = 0; trial < 200; ++trial) {
    const Plane plane_b = Plane::FromPointNormal(random.Point(3.0), random.UnitVector());
    const Pose3 T_a_b = random.RandomPose(5.0);
    const Plane plane_a = TransformPlane(T_a_b, plane_b);
    EXPECT_NEAR(plane_a.normal.norm(), 1.0, 1e-14);

    Eigen::Vector3d e1, e2;
    InPlaneBasis(plane_b.normal, &e1, &e2);
    for (int k = 0; k < 10; ++k) {
      const Eigen::Vector3d p_b =
          plane_b.ClosestPointToOrigin() + random.Uniform(-4.0, 4.0) * e1 + random.Uniform(-4.0, 4.0) * e2;
      ASSERT_NEAR(plane_b.SignedDistance(p_b), 0.0, 1e-12);
      const Eigen::Vector3d p_a = T_a_b * p_b;
      EXPECT_NEAR(plane_a.SignedDistance(p_a), 0.0, 1e-12) << "trial " << trial;  // [m]
    }
  }
}

TEST(TransformPlane, KeepsSignedDistancesOfPointsOffThePlane) {
  Random random(5);
  for (int trial = 0; trial < 100; ++trial) {
    const Plane plane_b = Plane::FromPointNormal(random.Point(2.0), random.UnitVector());
    const Pose3 T_a_b = random.RandomPose(5.0);
    const Plane plane_a = TransformPlane(T_a_b, plane_b);
    const Eigen::Vector3d x_b = random.Point(5.0);
    // A rigid motion keeps distances, and the side of the plane a point is on.
    EXPECT_NEAR(plane_a.SignedDistance(T_a_b * x_b), plane_b.SignedDistance(x_b), 1e-12);
  }
}

TEST(TransformPlane, ThereAndBackReturnsThePlane) {
  Random random(9);
  for (int trial = 0; trial < 200; ++trial) {
    const Plane plane_b = Plane::FromPointNormal(random.Point(3.0), random.UnitVector());
    const Pose3 T_a_b = random.RandomPose(5.0);
    const Plane back = TransformPlane(T_a_b.inverse(), TransformPlane(T_a_b, plane_b));
    EXPECT_NEAR((back.normal - plane_b.normal).norm(), 0.0, 1e-14);
    EXPECT_NEAR(back.offset, plane_b.offset, 1e-12);  // [m]
    EXPECT_TRUE(PlanesNear(back, plane_b, 1e-9, 1e-12));
  }
}

TEST(TransformPlane, PureTranslationShiftsTheOffset) {
  // Floor z = 0 in frame b; frame b sits 1.5 m above the origin of frame a, so the floor is z = 1.5 in a.
  const Plane floor_b{Eigen::Vector3d::UnitZ(), 0.0};
  Pose3 T_a_b = Pose3::Identity();
  T_a_b.translation() = Eigen::Vector3d(0.3, -0.2, 1.5);
  const Plane floor_a = TransformPlane(T_a_b, floor_b);
  EXPECT_NEAR((floor_a.normal - Eigen::Vector3d::UnitZ()).norm(), 0.0, 0.0);
  EXPECT_NEAR(floor_a.offset, -1.5, 1e-15);  // z - 1.5 = 0 [m]
  EXPECT_NEAR(floor_a.SignedDistance(Eigen::Vector3d(7.0, 3.0, 1.5)), 0.0, 1e-15);
}

TEST(IntersectRay, HitsAtTheAnalyticParameter) {
  // Plane z = 2 (n = +z, d = -2), ray from (1, 0, 0) along (0, 0.6, 0.8): hits at t = 2 / 0.8.
  const Plane plane{Eigen::Vector3d::UnitZ(), -2.0};
  const Eigen::Vector3d origin(1.0, 0.0, 0.0), dir(0.0, 0.6, 0.8);
  const std::optional<double> t = plane.IntersectRay(origin, dir);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 2.5, 1e-15);
  const Eigen::Vector3d hit = origin + *t * dir;
  EXPECT_NEAR((hit - Eigen::Vector3d(1.0, 1.5, 2.0)).norm(), 0.0, 1e-15);  // [m]
}

TEST(IntersectRay, RandomRaysHitPointsOnThePlane) {
  Random random(17);
  for (int trial = 0; trial < 200; ++trial) {
    const Plane plane = Plane::FromPointNormal(random.Point(3.0), random.UnitVector());
    // A ray from a random origin aimed at a random point of the plane, so the hit is at t = distance.
    Eigen::Vector3d e1, e2;
    InPlaneBasis(plane.normal, &e1, &e2);
    const Eigen::Vector3d target =
        plane.ClosestPointToOrigin() + random.Uniform(-3.0, 3.0) * e1 + random.Uniform(-3.0, 3.0) * e2;
    const Eigen::Vector3d origin = target + random.Uniform(0.2, 5.0) * random.UnitVector();
    const Eigen::Vector3d dir = (target - origin).normalized();
    if (std::abs(plane.normal.dot(dir)) < 1e-3) continue;  // grazing ray: t is ill-conditioned
    const std::optional<double> t = plane.IntersectRay(origin, dir);
    ASSERT_TRUE(t.has_value()) << "trial " << trial;
    EXPECT_NEAR(*t, (target - origin).norm(), 1e-9);  // [m]
    EXPECT_NEAR(plane.SignedDistance(origin + *t * dir), 0.0, 1e-12);
  }
}

TEST(IntersectRay, ParallelRayMisses) {
  const Plane plane{Eigen::Vector3d::UnitZ(), -2.0};
  EXPECT_FALSE(plane.IntersectRay(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.5, 0.0)).has_value());
  // Parallel but lying in the plane: still no single hit.
  EXPECT_FALSE(plane.IntersectRay(Eigen::Vector3d(0.0, 0.0, 2.0), Eigen::Vector3d::UnitX()).has_value());
  // Almost parallel, below the tolerance the caller asks for.
  EXPECT_FALSE(
      plane.IntersectRay(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.0, 1e-7), 1e-6).has_value());
  // The same ray with the default tolerance hits 2e7 m away.
  const std::optional<double> far = plane.IntersectRay(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.0, 1e-7));
  ASSERT_TRUE(far.has_value());
  EXPECT_NEAR(*far, 2e7, 1e-2);
}

TEST(IntersectRay, HitBehindTheOriginMisses) {
  const Plane plane{Eigen::Vector3d::UnitZ(), -2.0};  // z = 2
  // Looking down from z = 0: the plane is 2 m behind.
  EXPECT_FALSE(plane.IntersectRay(Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitZ()).has_value());
  // Above the plane looking up.
  EXPECT_FALSE(plane.IntersectRay(Eigen::Vector3d(0.0, 0.0, 3.0), Eigen::Vector3d::UnitZ()).has_value());
  // Above the plane looking down: hits 1 m ahead.
  const std::optional<double> t = plane.IntersectRay(Eigen::Vector3d(0.0, 0.0, 3.0), -Eigen::Vector3d::UnitZ());
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 1.0, 1e-15);
}

TEST(IntersectRay, SideOfTheNormalDoesNotMatter) {
  const Plane plane = Plane::FromPointNormal(Eigen::Vector3d(0.0, 0.0, 2.0), Eigen::Vector3d(0.0, 0.0, 1.0));
  const Eigen::Vector3d origin(0.5, 0.5, 0.0), dir = Eigen::Vector3d(0.0, 0.0, 1.0);
  const auto t = plane.IntersectRay(origin, dir);
  const auto t_flipped = plane.Flipped().IntersectRay(origin, dir);
  ASSERT_TRUE(t.has_value());
  ASSERT_TRUE(t_flipped.has_value());
  EXPECT_NEAR(*t, 2.0, 1e-15);
  EXPECT_NEAR(*t_flipped, 2.0, 1e-15);
}

TEST(NormalAngle, PerpendicularPlanesArePiOverTwo) {
  const Plane floor{Eigen::Vector3d::UnitZ(), 0.0};
  const Plane wall{Eigen::Vector3d::UnitX(), -3.0};
  EXPECT_NEAR(NormalAngle(floor, wall), M_PI / 2.0, 1e-15);

  Random random(23);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector3d n = random.UnitVector();
    Eigen::Vector3d e1, e2;
    InPlaneBasis(n, &e1, &e2);
    const Plane a = Plane::FromPointNormal(random.Point(2.0), n);
    const Plane b = Plane::FromPointNormal(random.Point(2.0), e1);
    EXPECT_NEAR(NormalAngle(a, b), M_PI / 2.0, 1e-12);
  }
}

TEST(NormalAngle, ParallelAndOppositePlanes) {
  const Plane a = Plane::FromPointNormal(Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::Vector3d(1.0, 1.0, 1.0));
  EXPECT_NEAR(NormalAngle(a, a), 0.0, 1e-15);
  EXPECT_NEAR(NormalAngle(a, a.Flipped()), M_PI, 1e-15);
  // 1e-7 rad apart: the atan2 form resolves it.
  const Plane b{Eigen::AngleAxisd(1e-7, Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitZ(), 0.0};
  EXPECT_NEAR(NormalAngle(Plane{Eigen::Vector3d::UnitZ(), 0.0}, b), 1e-7, 1e-15);
}

}  // namespace
}  // namespace planemap
