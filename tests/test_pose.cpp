// Rigid transforms: pose construction, rotation angle, interpolation, optical/body frames.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "planemap/core/pose.h"
#include "test_support.h"

namespace planemap {
namespace {

constexpr double kPi = M_PI;

TEST(MakePose, NormalisesANonUnitQuaternion) {
  // q = 3 * (cos 30deg, sin 30deg * z): a 60 deg rotation about z with norm 3.
  const double half = kPi / 6.0;
  const Eigen::Quaterniond q(3.0 * std::cos(half), 0.0, 0.0, 3.0 * std::sin(half));
  ASSERT_NEAR(q.norm(), 3.0, 1e-15);
  const Eigen::Vector3d t(1.0, -2.0, 0.5);  // [m]
  const Pose3 T = MakePose(q, t);

  const Eigen::Matrix3d R = T.linear();
  EXPECT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-14);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-14);
  EXPECT_NEAR(RotationAngle(R), kPi / 3.0, 1e-14);  // 60 deg [rad]
  // x axis rotated 60 deg about z.
  EXPECT_NEAR((R * Eigen::Vector3d::UnitX() - Eigen::Vector3d(0.5, std::sqrt(3.0) / 2.0, 0.0)).norm(), 0.0,
              1e-14);
  EXPECT_NEAR((T.translation() - t).norm(), 0.0, 0.0);  // translation kept exactly [m]
}

TEST(MakePose, NonUnitQuaternionMatchesUnitOne) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coef(-1.0, 1.0), scale(0.1, 10.0);
  for (int k = 0; k < 100; ++k) {
    const Eigen::Quaterniond unit =
        Eigen::Quaterniond(coef(rng), coef(rng), coef(rng), coef(rng)).normalized();
    const double s = scale(rng);
    const Eigen::Quaterniond scaled(s * unit.w(), s * unit.x(), s * unit.y(), s * unit.z());
    const Pose3 a = MakePose(unit, Eigen::Vector3d::Zero());
    const Pose3 b = MakePose(scaled, Eigen::Vector3d::Zero());
    EXPECT_NEAR((a.linear() - b.linear()).norm(), 0.0, 1e-14) << "scale " << s;
  }
}

TEST(RotationAngle, AccurateNearZero) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  const double angle = 1e-8;  // [rad]
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  // acos((trace - 1) / 2) would be off by ~1e-8 here; the atan2 form keeps ~1e-16 rad.
  EXPECT_NEAR(RotationAngle(R), angle, 1e-15);
  EXPECT_EQ(RotationAngle(Eigen::Matrix3d::Identity()), 0.0);
}

TEST(RotationAngle, AccurateNearPi) {
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 0.4, -0.8).normalized();
  for (double delta : {0.0, 1e-8, 1e-6, 1e-3}) {
    const double angle = kPi - delta;  // [rad]
    const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    const double measured = RotationAngle(R);
    EXPECT_NEAR(measured, angle, 1e-12) << "delta " << delta;
    EXPECT_LE(measured, kPi);
  }
}

TEST(RotationAngle, MatchesAngleAxisOverTheRange) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coef(-1.0, 1.0), angle_dist(0.0, kPi);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d axis = Eigen::Vector3d(coef(rng), coef(rng), coef(rng)).normalized();
    const double angle = angle_dist(rng);
    EXPECT_NEAR(RotationAngle(Eigen::AngleAxisd(angle, axis).toRotationMatrix()), angle, 1e-12);
  }
}

TEST(Interpolate, ReturnsEndpointsAtZeroAndOne) {
  const Pose3 a = MakePoseRpy(0.1, -0.2, 0.3, Eigen::Vector3d(1.0, 2.0, 3.0));
  const Pose3 b = MakePoseRpy(-0.4, 0.5, 1.2, Eigen::Vector3d(-1.0, 0.5, 2.0));
  const Pose3 at0 = Interpolate(a, b, 0.0);
  const Pose3 at1 = Interpolate(a, b, 1.0);
  EXPECT_NEAR(RotationAngle(at0.linear().transpose() * a.linear()), 0.0, 1e-12);
  EXPECT_NEAR((at0.translation() - a.translation()).norm(), 0.0, 1e-15);
  EXPECT_NEAR(RotationAngle(at1.linear().transpose() * b.linear()), 0.0, 1e-12);
  EXPECT_NEAR((at1.translation() - b.translation()).norm(), 0.0, 1e-15);
}

TEST(Interpolate, HalfwayIsHalfAngleAndMidTranslation) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coef(-1.0, 1.0), angle_dist(0.0, 3.0), metres(-5.0, 5.0);
  for (int k = 0; k < 50; ++k) {
    const Pose3 a = MakePoseRpy(coef(rng), coef(rng), coef(rng),
                                Eigen::Vector3d(metres(rng), metres(rng), metres(rng)));
    const Eigen::Vector3d axis = Eigen::Vector3d(coef(rng), coef(rng), coef(rng)).normalized();
    const double angle = angle_dist(rng);  // relative rotation a -> b [rad], below pi
    Pose3 b = Pose3::Identity();
    b.linear() = a.linear() * Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    b.translation() = Eigen::Vector3d(metres(rng), metres(rng), metres(rng));

    const Pose3 mid = Interpolate(a, b, 0.5);
    const Eigen::Matrix3d expected = a.linear() * Eigen::AngleAxisd(0.5 * angle, axis).toRotationMatrix();
    EXPECT_NEAR(RotationAngle(mid.linear().transpose() * expected), 0.0, 1e-9);
    EXPECT_NEAR(RotationAngle(a.linear().transpose() * mid.linear()), 0.5 * angle, 1e-9);
    EXPECT_NEAR(RotationAngle(mid.linear().transpose() * b.linear()), 0.5 * angle, 1e-9);
    EXPECT_NEAR((mid.translation() - 0.5 * (a.translation() + b.translation())).norm(), 0.0, 1e-12);
  }
}

TEST(Interpolate, TakesTheShortWayRound) {
  // b differs from a by 350 deg about z, i.e. -10 deg; the halfway pose is 5 deg away, not 175.
  const Pose3 a = MakePose(Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero());
  const Pose3 b = MakePose(Eigen::Quaterniond(Eigen::AngleAxisd(350.0 * kPi / 180.0, Eigen::Vector3d::UnitZ())),
                           Eigen::Vector3d::Zero());
  const Pose3 mid = Interpolate(a, b, 0.5);
  EXPECT_NEAR(RotationAngle(mid.linear()), 5.0 * kPi / 180.0, 1e-12);
}

TEST(RotationBodyFromOptical, MapsOpticalAxesToBodyAxes) {
  const Eigen::Matrix3d R = RotationBodyFromOptical();
  // Optical z (forward) -> body x (forward).
  EXPECT_NEAR((R * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitX()).norm(), 0.0, 0.0);
  // Optical x (right) -> body -y (y is left).
  EXPECT_NEAR((R * Eigen::Vector3d::UnitX() + Eigen::Vector3d::UnitY()).norm(), 0.0, 0.0);
  // Optical y (down) -> body -z (z is up).
  EXPECT_NEAR((R * Eigen::Vector3d::UnitY() + Eigen::Vector3d::UnitZ()).norm(), 0.0, 0.0);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-15);
  EXPECT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-15);
}

TEST(RotationBodyFromOptical, PointAheadOfCameraIsAheadOfBody) {
  // A point 2 m ahead, 0.5 m right and 0.3 m below the optical centre.
  const Eigen::Vector3d p_optical(0.5, 0.3, 2.0);
  const Eigen::Vector3d p_body = RotationBodyFromOptical() * p_optical;
  EXPECT_DOUBLE_EQ(p_body.x(), 2.0);   // forward [m]
  EXPECT_DOUBLE_EQ(p_body.y(), -0.5);  // right = negative left [m]
  EXPECT_DOUBLE_EQ(p_body.z(), -0.3);  // below = negative up [m]
}

}  // namespace
}  // namespace planemap
