// The simulated humanoid: footsteps within Nao-like limits, exact landing without noise, a
// plausible open-loop drift with noise, the head camera, Stop and replaced walks; and the
// Pose2 helpers it is built on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "planemap/nav/pose2.h"
#include "planemap/nav/simulated_humanoid.h"
#include "test_support.h"

namespace planemap::nav {
namespace {

using planemap::testing::Median;
using planemap::testing::ThrowsWith;

constexpr double kDeg = M_PI / 180.0;
constexpr double kRate = 30.0;  // camera frame rate [Hz]

double DistanceCm(const Pose2& a, const Pose2& b) { return 100.0 * (a.Position() - b.Position()).norm(); }
double AngleDeg(const Pose2& a, const Pose2& b) { return std::abs(WrapAngle(a.theta - b.theta)) / kDeg; }

HumanoidConfig NoiseFree() {
  HumanoidConfig c;
  c.bias_scale_std = c.bias_lateral_std = c.bias_yaw_deg_std = 0.0;
  c.step_noise_xy = c.step_noise_theta_deg = 0.0;
  return c;
}

// Advances at the camera rate until the walk is over; fails the test if it never ends.
void WalkToEnd(SimulatedHumanoid* h) {
  for (int frame = 0; h->IsWalking(); ++frame) {
    ASSERT_LT(frame, 100000) << "the walk does not end";
    h->Advance(1.0 / kRate);
  }
}

// Roll, pitch, yaw [deg] of the head relative to the base (R = Rz(yaw) Ry(pitch) Rx(roll)).
Eigen::Vector3d HeadRpyDeg(const Pose3& T_base_camera) {
  const Eigen::Matrix3d R = T_base_camera.linear() * RotationBodyFromOptical().transpose();
  return Eigen::Vector3d(std::atan2(R(2, 1), R(2, 2)), -std::asin(R(2, 0)), std::atan2(R(1, 0), R(0, 0))) /
         kDeg;
}

// ---- Pose2 helpers ----

TEST(Pose2, WrapAngleIsIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(WrapAngle(M_PI), M_PI);
  EXPECT_DOUBLE_EQ(WrapAngle(-M_PI), M_PI);
  EXPECT_NEAR(WrapAngle(3.0 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(WrapAngle(-370.0 * kDeg) / kDeg, -10.0, 1e-9);
  EXPECT_NEAR(WrapAngle(710.0 * kDeg) / kDeg, -10.0, 1e-9);
}

TEST(Pose2, ComposeInverseAndBetweenRoundTrip) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(-3.0, 3.0), ang(-M_PI, M_PI);
  for (int i = 0; i < 100; ++i) {
    const Pose2 a{pos(rng), pos(rng), ang(rng)}, b{pos(rng), pos(rng), ang(rng)};
    const Pose2 b_again = Compose(a, Between(a, b));
    EXPECT_LT(DistanceCm(b_again, b), 1e-9);
    EXPECT_LT(AngleDeg(b_again, b), 1e-9);
    const Pose2 identity = Compose(a, Inverse(a));
    EXPECT_LT(DistanceCm(identity, Pose2{}), 1e-9);
    EXPECT_LT(AngleDeg(identity, Pose2{}), 1e-9);
    const Pose2 a_again = Inverse(Inverse(a));
    EXPECT_LT(DistanceCm(a_again, a), 1e-9);
    // Compose agrees with 3-D poses on the floor.
    const Pose3 ab = ToPose3(a) * ToPose3(b);
    EXPECT_TRUE(planemap::testing::PosesNear(ToPose3(Compose(a, b)), ab, 1e-9, 1e-12));
  }
}

TEST(Pose2, BetweenIsTheMotionInTheFirstPosesFrame) {
  // Facing +y at (1, 0): a point 1 m further along +y is 1 m straight ahead.
  const Pose2 rel = Between({1.0, 0.0, M_PI / 2}, {1.0, 1.0, M_PI});
  EXPECT_NEAR(rel.x, 1.0, 1e-12);
  EXPECT_NEAR(rel.y, 0.0, 1e-12);
  EXPECT_NEAR(rel.theta / kDeg, 90.0, 1e-9);
}

// ---- Footsteps without noise ----

struct WalkCase {
  std::string name;
  std::vector<Pose2> moves;  // MoveTo commands, each walked to the end
  int steps;                 // footsteps expected in all
};

class NoiseFreeWalk : public ::testing::TestWithParam<WalkCase> {};

TEST_P(NoiseFreeWalk, LandsOnTheComposedGoalsWithinTheStepLimits) {
  const HumanoidConfig c = NoiseFree();
  const Pose2 start{1.0, 2.0, 0.3};
  SimulatedHumanoid h(c, start, 1);
  Pose2 goal = start, previous = start;
  for (const Pose2& move : GetParam().moves) {
    goal = Compose(goal, move);
    h.MoveTo(move.x, move.y, move.theta);
    // Sampled at the step boundaries, the base moves one footstep at a time.
    while (h.IsWalking()) {
      h.Advance(c.step_duration);
      const Pose2 step = Between(previous, h.TruePose());
      EXPECT_LE(std::abs(step.x), c.max_step_x + 1e-12);
      EXPECT_LE(std::abs(step.y), c.max_step_y + 1e-12);
      EXPECT_LE(std::abs(step.theta) / kDeg, c.max_step_theta_deg + 1e-9);
      previous = h.TruePose();
    }
    EXPECT_LT(DistanceCm(h.TruePose(), goal), 0.1);  // < 1 mm
    EXPECT_LT(AngleDeg(h.TruePose(), goal), 0.01);
    EXPECT_LT(DistanceCm(h.OdometryPose(), h.TruePose()), 1e-9);
  }
  EXPECT_EQ(static_cast<int>(h.Footsteps().size()), GetParam().steps);
  EXPECT_NEAR(h.Time(), GetParam().steps * c.step_duration, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(
    Humanoid, NoiseFreeWalk,
    ::testing::Values(
        // 0.5 m / 4 cm = 12.5: 13 steps.
        WalkCase{"Forward", {{0.5, 0.0, 0.0}}, 13}, WalkCase{"Backward", {{-0.2, 0.0, 0.0}}, 5},
        // Sideways is the slow direction: 10 cm / 2 cm.
        WalkCase{"Diagonal", {{0.1, 0.1, 0.0}}, 5}, WalkCase{"TurnLeft90", {{0.0, 0.0, 90 * kDeg}}, 9},
        WalkCase{"TurnAround", {{0.0, 0.0, 180 * kDeg}}, 18},
        // A quarter circle of radius 0.5 m is 0.785 m long: 20 steps of 3.9 cm.
        WalkCase{"QuarterCircle", {{0.5, 0.5, 90 * kDeg}}, 20},
        // One step's worth in each component, but turning bends the step past the sideways limit.
        WalkCase{"AllLimitsAtOnce", {{0.04, 0.02, 10 * kDeg}}, 2},
        WalkCase{"Sequence", {{0.5, 0.0, 0.0}, {0.0, 0.0, -90 * kDeg}, {0.3, -0.05, 45 * kDeg}}, 13 + 9 + 9}),
    [](const ::testing::TestParamInfo<WalkCase>& param_info) { return param_info.param.name; });

TEST(Humanoid, FootstepsAlternateBesideTheBase) {
  const HumanoidConfig c = NoiseFree();
  SimulatedHumanoid h(c, {}, 1);
  h.MoveTo(0.3, 0.0, 30 * kDeg);
  WalkToEnd(&h);
  const std::vector<Footstep>& feet = h.Footsteps();
  ASSERT_GE(feet.size(), 2u);
  for (size_t i = 0; i < feet.size(); ++i) {
    EXPECT_EQ(feet[i].left, i % 2 == 0);
    EXPECT_NEAR(feet[i].time, (i + 1) * c.step_duration, 1e-9);
  }
  // The last foot lands half the foot separation beside the final base pose.
  const Pose2 last_in_base = Between(h.TruePose(), feet.back().foot);
  EXPECT_NEAR(last_in_base.x * 100.0, 0.0, 1e-9);
  EXPECT_NEAR(std::abs(last_in_base.y) * 100.0, 0.5 * c.foot_separation * 100.0, 1e-9);
}

TEST(Humanoid, ZeroMoveTakesNoTimeAndNoNoise) {
  const HumanoidConfig c;  // default noise
  SimulatedHumanoid a(c, {}, 5), b(c, {}, 5);
  a.MoveTo(0.0, 0.0, 0.0);
  EXPECT_FALSE(a.IsWalking());
  EXPECT_TRUE(a.Footsteps().empty());
  a.Advance(1.0);
  b.Advance(1.0);
  EXPECT_EQ(DistanceCm(a.TruePose(), Pose2{}), 0.0);
  // The zero move drew no noise: both robots then walk identically.
  a.MoveTo(0.3, 0.0, 0.0);
  b.MoveTo(0.3, 0.0, 0.0);
  WalkToEnd(&a);
  WalkToEnd(&b);
  EXPECT_EQ(a.TruePose().x, b.TruePose().x);
  EXPECT_EQ(a.TruePose().y, b.TruePose().y);
  EXPECT_EQ(a.TruePose().theta, b.TruePose().theta);
}

// ---- Noise: determinism and open-loop drift ----

// The 2 m open-loop walk of the paper's first scenario: four times MoveTo(0.5, 0, 0).
SimulatedHumanoid OpenLoopWalk(std::uint64_t seed) {
  SimulatedHumanoid h(HumanoidConfig{}, {}, seed);
  for (int i = 0; i < 4; ++i) {
    h.MoveTo(0.5, 0.0, 0.0);
    WalkToEnd(&h);
  }
  return h;
}

TEST(Humanoid, SameSeedSameWalkOtherSeedOtherWalk) {
  const SimulatedHumanoid a = OpenLoopWalk(3), b = OpenLoopWalk(3), c = OpenLoopWalk(4);
  ASSERT_EQ(a.Footsteps().size(), b.Footsteps().size());
  for (size_t i = 0; i < a.Footsteps().size(); ++i) {
    EXPECT_EQ(a.Footsteps()[i].foot.x, b.Footsteps()[i].foot.x);
    EXPECT_EQ(a.Footsteps()[i].foot.y, b.Footsteps()[i].foot.y);
    EXPECT_EQ(a.Footsteps()[i].foot.theta, b.Footsteps()[i].foot.theta);
  }
  EXPECT_GT(DistanceCm(a.TruePose(), c.TruePose()), 0.1);
}

TEST(Humanoid, OpenLoopDriftOverTwoMetresIsLikeARealNao) {
  std::vector<double> errors_cm;
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const SimulatedHumanoid h = OpenLoopWalk(seed);
    // The robot believes it walked exactly 2 m straight on: 4 x 13 steps.
    EXPECT_LT(DistanceCm(h.OdometryPose(), Pose2{2.0, 0.0, 0.0}), 1e-6);
    EXPECT_EQ(h.Footsteps().size(), 52u);
    errors_cm.push_back(DistanceCm(h.TruePose(), h.OdometryPose()));
  }
  // The paper's open-loop run ended 24.5 cm off; per-step noise alone (a few mm) would give
  // ~2 cm and a perfect gait 0, so this checks the systematic errors matter as they do on a robot.
  const double median_cm = Median(errors_cm);
  EXPECT_GT(median_cm, 5.0);
  EXPECT_LT(median_cm, 40.0);
  EXPECT_LT(*std::max_element(errors_cm.begin(), errors_cm.end()), 100.0);
}

// ---- The head camera ----

TEST(Humanoid, StandingCameraGivesBackTheBasePoseAtTheConfiguredHeightAndPitch) {
  const HumanoidConfig c;
  SimulatedHumanoid h(c, {0.5, -1.0, 2.0}, 9);
  for (int stage = 0; stage < 2; ++stage) {  // before and after a noisy walk
    ASSERT_FALSE(h.IsWalking());
    const Pose3 T_world_camera = h.CameraPose();
    const Pose2 base = BaseFromCamera(T_world_camera, c.camera_forward_offset);
    EXPECT_LT(DistanceCm(base, h.TruePose()), 0.01);  // < 0.1 mm
    EXPECT_LT(AngleDeg(base, h.TruePose()), 1e-6);
    EXPECT_NEAR(T_world_camera.translation().z() * 100.0, c.camera_height * 100.0, 1e-9);
    const double pitch_down_deg = std::asin(-T_world_camera.linear().col(2).z()) / kDeg;
    EXPECT_NEAR(pitch_down_deg, c.camera_pitch_deg, 1e-9);
    h.MoveTo(0.4, 0.1, 40 * kDeg);
    WalkToEnd(&h);
  }
}

TEST(Humanoid, WalkingCameraSwaysWithinTheConfiguredAmplitudesAndMovesSmoothly) {
  const HumanoidConfig c;
  SimulatedHumanoid h(c, {}, 2);
  h.MoveTo(1.0, 0.0, 0.0);
  Eigen::Vector3d peak_offset = Eigen::Vector3d::Zero(), peak_rpy = Eigen::Vector3d::Zero();
  Eigen::Vector3d previous = h.CameraPose().translation();
  double largest_jump_cm = 0.0;
  while (h.IsWalking()) {
    h.Advance(1.0 / kRate);
    const Pose3 T_base_camera = ToPose3(h.TruePose()).inverse() * h.CameraPose();
    const Eigen::Vector3d offset = T_base_camera.translation();
    EXPECT_NEAR(offset.x() * 100.0, c.camera_forward_offset * 100.0, 1e-9);
    EXPECT_GE(offset.z() * 100.0, c.camera_height * 100.0 - 1e-9);
    peak_offset = peak_offset.cwiseMax(offset.cwiseAbs());
    const Eigen::Vector3d rpy = HeadRpyDeg(T_base_camera);
    EXPECT_NEAR(rpy.y(), c.camera_pitch_deg, 1e-6);
    peak_rpy = peak_rpy.cwiseMax(rpy.cwiseAbs());
    largest_jump_cm = std::max(largest_jump_cm, 100.0 * (h.CameraPose().translation() - previous).norm());
    previous = h.CameraPose().translation();
  }
  // Reaches, but never exceeds, each amplitude (frames fall near the sway peaks).
  EXPECT_LE(peak_offset.y() * 100.0, c.sway_lateral * 100.0 + 1e-9);
  EXPECT_GT(peak_offset.y() * 100.0, 0.95 * c.sway_lateral * 100.0);
  EXPECT_LE((peak_offset.z() - c.camera_height) * 100.0, c.sway_vertical * 100.0 + 1e-9);
  EXPECT_GT((peak_offset.z() - c.camera_height) * 100.0, 0.95 * c.sway_vertical * 100.0);
  EXPECT_LE(peak_rpy.x(), c.sway_roll_deg + 1e-9);
  EXPECT_GT(peak_rpy.x(), 0.95 * c.sway_roll_deg);
  EXPECT_LE(peak_rpy.z(), c.sway_yaw_deg + 1e-9);
  EXPECT_GT(peak_rpy.z(), 0.95 * c.sway_yaw_deg);
  // Continuous at 30 Hz: a 4 cm step in 0.5 s moves the head at most a few mm a frame.
  EXPECT_LT(largest_jump_cm, 1.0);
}

// ---- Stop and replaced walks ----

TEST(Humanoid, StopEndsWithinOneStep) {
  const HumanoidConfig c = NoiseFree();
  SimulatedHumanoid h(c, {}, 1);
  h.MoveTo(1.0, 0.0, 0.0);
  h.Advance(2.5 * c.step_duration);  // half-way through the third step
  h.Stop();
  EXPECT_TRUE(h.IsWalking());  // a foot in the air comes down first
  h.Advance(0.5 * c.step_duration);
  EXPECT_FALSE(h.IsWalking());
  EXPECT_EQ(h.Footsteps().size(), 3u);
  const Pose2 stopped = h.TruePose();
  EXPECT_NEAR(stopped.x * 100.0, 3.0 * 100.0 / 25.0, 1e-9);  // 1 m in 25 steps of 4 cm
  h.Advance(5.0);
  EXPECT_EQ(DistanceCm(h.TruePose(), stopped), 0.0);
}

TEST(Humanoid, NewMoveToReplacesTheWalkAfterTheCurrentStep) {
  const HumanoidConfig c = NoiseFree();
  SimulatedHumanoid h(c, {}, 1);
  h.MoveTo(1.0, 0.0, 0.0);
  h.Advance(2.5 * c.step_duration);
  const Pose2 move{0.0, 0.2, 90 * kDeg};
  const Pose2 goal = Compose(h.OdometryPose(), move);  // relative to where the base is now
  h.MoveTo(move.x, move.y, move.theta);
  WalkToEnd(&h);
  EXPECT_LT(DistanceCm(h.TruePose(), goal), 0.1);
  EXPECT_LT(AngleDeg(h.TruePose(), goal), 0.01);
  // The third step still went straight on: the first walk's 4 cm.
  ASSERT_GE(h.Footsteps().size(), 4u);
  EXPECT_NEAR(Between(h.Footsteps()[0].foot, h.Footsteps()[2].foot).x * 100.0, 8.0, 1e-9);
}

// ---- Bad input ----

TEST(Humanoid, RejectsBadConfigAndBadTime) {
  HumanoidConfig bad;
  bad.max_step_x = 0.0;
  EXPECT_TRUE(ThrowsWith([&] { SimulatedHumanoid unused(bad, {}, 1); }, {"humanoid.max_step_x"}));
  SimulatedHumanoid h(HumanoidConfig{}, {}, 1);
  EXPECT_THROW(h.Advance(-0.1), std::invalid_argument);
  EXPECT_THROW(h.MoveTo(std::nan(""), 0.0, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace planemap::nav
