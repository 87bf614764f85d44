// Odometry calibration: the simulated humanoid's per-run gait bias (forward scale, sideways drift)
// is learnt from measured base poses while it walks, and the corrected odometry then follows the
// true walk better than the raw one where nothing is measured.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <vector>

#include "planemap/nav/odometry_calibration.h"
#include "planemap/nav/simulated_humanoid.h"
#include "test_support.h"

namespace planemap::nav {
namespace {

using planemap::testing::Median;

constexpr double kDeg = M_PI / 180.0;
constexpr double kRate = 15.0;  // camera frame rate [Hz]

// Four metres in legs with turns between them, as on the way to a box across a room.
const std::vector<Pose2> kLegs = {{0.5, 0.0, 0.0},         {0.5, 0.0, 0.0}, {0.0, 0.0, 90 * kDeg},
                                  {0.5, 0.05, 0.0},        {0.5, 0.0, 0.0}, {0.0, 0.0, -60 * kDeg},
                                  {0.5, -0.05, 10 * kDeg}, {0.5, 0.0, 0.0}, {0.5, 0.0, 0.0},
                                  {0.5, 0.0, 0.0}};

struct Walker {
  SimulatedHumanoid robot;
  OdometryCalibration calibration{OdometryCalibrationConfig{}};
  std::mt19937_64 rng;
  Pose2 corrected;  // the calibration's odometry at the last frame

  Walker(const HumanoidConfig& config, std::uint64_t seed) : robot(config, Pose2{}, seed), rng(seed) {}

  // Walks `leg` at the camera rate until the robot has stood for 10 frames. Every frame the
  // calibration corrects the odometry and, if `measured`, observes the base pose under the swaying
  // head camera with 2 mm of noise (the tracker's, on a tracked frame).
  void Walk(const Pose2& leg, bool measured) {
    std::normal_distribution<double> noise(0.0, 0.002);
    robot.MoveTo(leg.x, leg.y, leg.theta);
    for (int frame = 0, still = 0; still < 10; ++frame) {
      ASSERT_LT(frame, 100000) << "the walk does not end";
      corrected = calibration.Correct(robot.OdometryPose());
      Pose2 base = BaseFromCamera(robot.CameraPose(), robot.config().camera_forward_offset);
      base.x += noise(rng);
      base.y += noise(rng);
      calibration.Observe(measured ? std::optional<Pose2>(base) : std::nullopt);
      robot.Advance(1.0 / kRate);
      still = robot.IsWalking() ? 0 : still + 1;
    }
  }
};

struct Errors {
  std::vector<double> scale, lateral;              // |estimate - truth| [% and cm/m]
  std::vector<double> scale_bias, lateral_bias;    // |truth|
  std::vector<double> scale_sigmas, lateral_sigmas;  // |estimate - truth| / stated std
};

Errors CalibrateOverSeeds(const HumanoidConfig& config) {
  Errors e;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    Walker w(config, seed);
    for (const Pose2& leg : kLegs) w.Walk(leg, true);
    EXPECT_NEAR(w.calibration.CalibratedDistance(), 4.0, 0.3) << "seed " << seed;  // the legs' length
    const Eigen::Vector2d std = w.calibration.Covariance().diagonal().cwiseSqrt();
    const double ds = w.calibration.Scale() - w.robot.BiasScale();
    const double dl = w.calibration.Lateral() - w.robot.BiasLateral();
    e.scale.push_back(100.0 * std::abs(ds));
    e.lateral.push_back(100.0 * std::abs(dl));
    e.scale_bias.push_back(100.0 * std::abs(w.robot.BiasScale()));
    e.lateral_bias.push_back(100.0 * std::abs(w.robot.BiasLateral()));
    e.scale_sigmas.push_back(std::abs(ds) / std.x());
    e.lateral_sigmas.push_back(std::abs(dl) / std.y());
  }
  return e;
}

void Print(const Errors& e) {
  std::printf("scale error median %.2f %% (bias %.2f %%), sideways %.2f cm/m (bias %.2f cm/m)\n",
              Median(e.scale), Median(e.scale_bias), Median(e.lateral), Median(e.lateral_bias));
}

TEST(OdometryCalibration, RecoversTheBiasOfAGaitWithoutRandomStepErrors) {
  HumanoidConfig config;  // bias as by default, head sway, but no random step error
  config.step_noise_xy = config.step_noise_theta_deg = 0.0;
  const Errors e = CalibrateOverSeeds(config);
  Print(e);
  // What is left is the model's: the heading measured within a step already holds part of that
  // step's turn bias (0.3 deg std), which turns the odometry's increments by about half of it.
  EXPECT_LT(Median(e.scale), 0.2);    // [%]
  EXPECT_LT(Median(e.lateral), 0.2);  // [cm per m]
  for (double v : e.scale) EXPECT_LT(v, 0.5);
  for (double v : e.lateral) EXPECT_LT(v, 0.5);
}

TEST(OdometryCalibration, LearnsTheGaitsBiasToWithinItsStatedUncertainty) {
  const Errors e = CalibrateOverSeeds(HumanoidConfig{});
  Print(e);
  // The random step errors (3 mm a step) bound what 4 m can tell: about 1 %, the stated standard
  // deviation; no run is off by more than 4 of them, and the bias is learnt to a fraction of itself.
  for (double v : e.scale_sigmas) EXPECT_LT(v, 4.0);
  for (double v : e.lateral_sigmas) EXPECT_LT(v, 4.0);
  EXPECT_LT(Median(e.scale), 0.6 * Median(e.scale_bias));
  EXPECT_LT(Median(e.lateral), 0.6 * Median(e.lateral_bias));
}

// After the calibrated walk, a last unmeasured half metre, as toward a box whose faces have left
// the image: the corrected odometry ends nearer the true motion than the raw odometry does.
TEST(OdometryCalibration, CorrectedOdometryDriftsLessOverAnUnmeasuredLastLeg) {
  std::vector<double> raw_cm, corrected_cm;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    Walker w(HumanoidConfig{}, seed);
    for (const Pose2& leg : kLegs) w.Walk(leg, true);
    const Pose2 truth0 = w.robot.TruePose(), raw0 = w.robot.OdometryPose(), corrected0 = w.corrected;
    w.Walk({0.4, -0.2, 20 * kDeg}, false);
    const Pose2 truth = Between(truth0, w.robot.TruePose());
    raw_cm.push_back(100.0 * (Between(raw0, w.robot.OdometryPose()).Position() - truth.Position()).norm());
    corrected_cm.push_back(100.0 * (Between(corrected0, w.corrected).Position() - truth.Position()).norm());
  }
  std::printf("error over the last leg, median: raw %.2f cm, corrected %.2f cm\n", Median(raw_cm),
              Median(corrected_cm));
  EXPECT_LT(Median(corrected_cm), 0.75 * Median(raw_cm));
}

TEST(OdometryCalibration, StaysAtZeroUntilTheRobotHasWalkedMeasured) {
  Walker w(HumanoidConfig{}, 7);
  for (const Pose2& leg : kLegs) w.Walk(leg, false);  // nothing measured
  EXPECT_EQ(w.calibration.Scale(), 0.0);
  EXPECT_EQ(w.calibration.Lateral(), 0.0);
  EXPECT_EQ(w.calibration.CalibratedDistance(), 0.0);
  // The corrected odometry is then the raw one, moved by the same motions.
  EXPECT_NEAR(w.corrected.x, w.robot.OdometryPose().x, 1e-9);
  EXPECT_NEAR(w.corrected.y, w.robot.OdometryPose().y, 1e-9);
}

TEST(OdometryCalibration, DisabledPassesTheOdometryThrough) {
  OdometryCalibrationConfig config;
  config.enabled = false;
  OdometryCalibration c(config);
  const Pose2 p{1.0, 2.0, 0.3};
  c.Observe(Pose2{5.0, 5.0, 0.0});
  const Pose2 out = c.Correct(p);
  EXPECT_EQ(out.x, p.x);
  EXPECT_EQ(out.y, p.y);
  EXPECT_EQ(out.theta, p.theta);
}

TEST(OdometryCalibration, RejectsAnInvalidConfig) {
  OdometryCalibrationConfig config;
  config.end_pose_std = 0.0;
  EXPECT_THROW(OdometryCalibration{config}, std::invalid_argument);
}

}  // namespace
}  // namespace planemap::nav
