// Trajectory evaluation: ATE after a rigid alignment, RPE over a time delta, stamp association
// and the errors for unusable input.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "planemap/core/error.h"
#include "planemap/core/trajectory_eval.h"
#include "test_support.h"

namespace planemap {
namespace {

using planemap::testing::PosesNear;
using planemap::testing::ThrowsWith;

constexpr double kDeg = M_PI / 180.0;
constexpr double kStart = 1305031102.0;  // a TUM-sized stamp [s]
constexpr double kRate = 30.0;           // [Hz]

// A camera on a rising, turning helix: n poses at 30 Hz.
Trajectory Helix(int n) {
  Trajectory trajectory;
  for (int k = 0; k < n; ++k) {
    const double t = k / kRate;
    const Eigen::Vector3d position(2.0 * std::cos(0.3 * t), 1.5 * std::sin(0.3 * t), 0.5 + 0.05 * t);
    trajectory.push_back({kStart + t, MakePoseRpy(0.1 * std::sin(t), -0.3 + 0.05 * t, 0.3 * t + M_PI / 2, position)});
  }
  return trajectory;
}

// Every pose moved by T (the same path in another world frame).
Trajectory Moved(const Pose3& T, const Trajectory& trajectory) {
  Trajectory moved = trajectory;
  for (StampedPose& pose : moved) pose.T_world_camera = T * pose.T_world_camera;
  return moved;
}

EvalConfig Config(double rpe_delta = 1.0) {
  EvalConfig config;
  config.rpe_delta = rpe_delta;
  return config;
}

// --- ATE ---------------------------------------------------------------------------------------

class AteOfMovedCopy : public ::testing::TestWithParam<Pose3> {};

TEST_P(AteOfMovedCopy, IsZeroAndTheAlignmentRecoversTheMotion) {
  const Trajectory groundtruth = Helix(150);
  const Pose3 T_estimate_groundtruth = GetParam();
  const TrajectoryEvaluation result =
      EvaluateTrajectory(groundtruth, Moved(T_estimate_groundtruth, groundtruth), Config(), "gt.txt", "est.txt");
  EXPECT_EQ(result.pairs, 150u);
  EXPECT_EQ(result.ate.translation.count, 150u);
  EXPECT_LT(result.ate.translation.max, 1e-9) << "ATE max [m]";
  EXPECT_LT(result.rpe.translation.max, 1e-9) << "RPE translation max [m]";
  EXPECT_LT(result.rpe.rotation.max, 1e-6) << "RPE rotation max [deg]";
  EXPECT_TRUE(PosesNear(result.ate.T_groundtruth_estimate, T_estimate_groundtruth.inverse(), 1e-9 / kDeg, 1e-9));
  EXPECT_TRUE(PosesNear(result.T_groundtruth_estimate_first, T_estimate_groundtruth.inverse(), 1e-9 / kDeg, 1e-9));
}

INSTANTIATE_TEST_SUITE_P(
    Transforms, AteOfMovedCopy,
    ::testing::Values(Pose3::Identity(), MakePoseRpy(0.0, 0.0, 90.0 * kDeg, Eigen::Vector3d(1.0, -2.0, 0.0)),
                      MakePoseRpy(0.7, -1.2, 2.9, Eigen::Vector3d(-3.0, 0.5, 7.0)),
                      MakePoseRpy(3.0, 0.4, -2.0, Eigen::Vector3d(1000.0, 2000.0, -50.0))));

TEST(Ate, CentimetreOffsetOnTwoOfEightPosesGivesTheRmseComputedByHand) {
  // Positions on the corners of a 2 m cube; the estimate lifts the opposite corners (1,1,1) and
  // (-1,-1,-1) by 1 cm. Their positions sum to zero, so the best rigid alignment is a pure shift
  // by the mean offset, 2/8 cm down: residuals 0.75 cm on those two and 0.25 cm on the other six.
  Trajectory groundtruth, estimate;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner(k & 1 ? 1.0 : -1.0, k & 2 ? 1.0 : -1.0, k & 4 ? 1.0 : -1.0);
    const Pose3 T = MakePoseRpy(0.2 * k, -0.1 * k, 0.7 * k, corner);
    groundtruth.push_back({kStart + 0.1 * k, T});
    estimate.push_back({kStart + 0.1 * k, T});
    if (k == 0 || k == 7) estimate.back().T_world_camera.translation().z() += 0.01;
  }
  const AteResult ate = ComputeAte(AssociatePoses(groundtruth, estimate, 0.02));
  ASSERT_EQ(ate.translation.count, 8u);
  EXPECT_NEAR(ate.translation.rmse * 100.0, std::sqrt((2 * 0.75 * 0.75 + 6 * 0.25 * 0.25) / 8), 1e-9) << "RMSE [cm]";
  EXPECT_NEAR(ate.translation.mean * 100.0, (2 * 0.75 + 6 * 0.25) / 8, 1e-9) << "mean [cm]";
  EXPECT_NEAR(ate.translation.median * 100.0, 0.25, 1e-9) << "median [cm]";
  EXPECT_NEAR(ate.translation.max * 100.0, 0.75, 1e-9) << "max [cm]";
  EXPECT_TRUE(PosesNear(ate.T_groundtruth_estimate, MakePose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, -0.0025)),
                        1e-9, 1e-12));
}

TEST(Ate, FewerThanThreePairsGiveNoResult) {
  const Trajectory groundtruth = Helix(2);
  EXPECT_EQ(ComputeAte(AssociatePoses(groundtruth, groundtruth, 0.02)).translation.count, 0u);
}

// --- RPE ---------------------------------------------------------------------------------------

TEST(Rpe, ConstantTranslationDriftPerSecondIsTheTranslationalRpe) {
  // The estimate drifts 1 cm/s along world x: every motion over delta seconds is off by delta cm.
  const Trajectory groundtruth = Helix(301);
  Trajectory estimate = groundtruth;
  const Eigen::Vector3d drift(0.01, 0.0, 0.0);  // [m/s]
  for (StampedPose& pose : estimate) pose.T_world_camera.translation() += (pose.stamp - kStart) * drift;
  const AssociatedPoses poses = AssociatePoses(groundtruth, estimate, 0.02);
  for (double delta : {1.0, 2.0}) {
    const RpeResult rpe = ComputeRpe(poses, delta, 0.02);
    EXPECT_DOUBLE_EQ(rpe.delta, delta);
    EXPECT_EQ(rpe.translation.count, static_cast<size_t>(301 - delta * kRate)) << "pairs " << delta << " s apart";
    EXPECT_NEAR(rpe.translation.rmse * 100.0, delta, 1e-7) << "RPE RMSE [cm] over " << delta << " s";
    EXPECT_NEAR(rpe.translation.max * 100.0, delta, 1e-7) << "RPE max [cm] over " << delta << " s";
    EXPECT_LT(rpe.rotation.max, 1e-6) << "RPE rotation [deg]";
  }
}

TEST(Rpe, ConstantYawDriftIsTheRotationalRpe) {
  // The estimate's world turns 0.5 deg/s about z: the motion over 1 s is off by 0.5 deg.
  const Trajectory groundtruth = Helix(301);
  Trajectory estimate = groundtruth;
  for (StampedPose& pose : estimate) {
    const Pose3 drift = MakePoseRpy(0.0, 0.0, 0.5 * kDeg * (pose.stamp - kStart), Eigen::Vector3d::Zero());
    pose.T_world_camera = drift * pose.T_world_camera;
  }
  const RpeResult rpe = ComputeRpe(AssociatePoses(groundtruth, estimate, 0.02), 1.0, 0.02);
  ASSERT_EQ(rpe.rotation.count, 271u);
  EXPECT_NEAR(rpe.rotation.rmse, 0.5, 1e-7) << "RPE rotation RMSE [deg]";
  EXPECT_NEAR(rpe.rotation.max, 0.5, 1e-7) << "RPE rotation max [deg]";
  EXPECT_NEAR(rpe.rotation.median, 0.5, 1e-7) << "RPE rotation median [deg]";
}

TEST(Rpe, PairsAcrossAGapAreSkipped) {
  // 0.5 s missing at 4-4.5 s: no pose has a partner 1 s later that lands in the gap.
  Trajectory trajectory;
  for (const StampedPose& pose : Helix(301)) {
    const double t = pose.stamp - kStart;
    if (t < 4.0 - 1e-9 || t > 4.5 + 1e-9) trajectory.push_back(pose);
  }
  const RpeResult rpe = ComputeRpe(AssociatePoses(trajectory, trajectory, 0.02), 1.0, 0.02);
  // Of the 271 pairs of the full run, those starting at 3.0..3.5 s (16) and 4.0..4.5 s (16) are gone.
  EXPECT_EQ(rpe.translation.count, 271u - 32u);
}

// --- Association -------------------------------------------------------------------------------

TEST(AssociatePoses, JitteredStampsPairWithTheGroundTruthTheyWereTakenFrom) {
  // Ground truth at 100 Hz; the estimate is every third of its poses with its stamp moved up to
  // +-4 ms (less than half the 10 ms spacing), so association must undo the jitter exactly.
  Trajectory groundtruth;
  for (int k = 0; k < 600; ++k) {
    groundtruth.push_back({kStart + 0.01 * k, MakePoseRpy(0.0, 0.0, 0.01 * k, Eigen::Vector3d(0.01 * k, 0.0, 0.5))});
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.004, 0.004);  // [s]
  Trajectory estimate;
  for (size_t k = 0; k < groundtruth.size(); k += 3) estimate.push_back({groundtruth[k].stamp + jitter(rng), groundtruth[k].T_world_camera});
  const TrajectoryEvaluation result = EvaluateTrajectory(groundtruth, estimate, Config(), "gt.txt", "est.txt");
  EXPECT_EQ(result.pairs, estimate.size());
  EXPECT_LT(result.ate.translation.max, 1e-9) << "ATE max [m]: a pose paired with a neighbour moves 1 cm";
}

TEST(AssociatePoses, StampsFurtherApartThanTheGapDoNotPair) {
  const Trajectory groundtruth = Helix(30);
  Trajectory estimate = groundtruth;
  for (StampedPose& pose : estimate) pose.stamp += 0.0125;  // 12.5 ms: inside 20 ms, outside 10 ms
  EXPECT_EQ(AssociatePoses(groundtruth, estimate, 0.02).size(), 30u);
  EXPECT_EQ(AssociatePoses(groundtruth, estimate, 0.01).size(), 0u);
}

// --- Errors ------------------------------------------------------------------------------------

TEST(EvaluateTrajectory, EmptyTrajectoriesAreErrorsNamingTheFile) {
  const Trajectory helix = Helix(60);
  EXPECT_THROW(EvaluateTrajectory({}, helix, Config(), "gt.txt", "est.txt"), InputError);
  EXPECT_TRUE(ThrowsWith([&] { EvaluateTrajectory({}, helix, Config(), "gt.txt", "est.txt"); },
                         {"gt.txt: the trajectory has no poses"}));
  EXPECT_TRUE(ThrowsWith([&] { EvaluateTrajectory(helix, {}, Config(), "gt.txt", "est.txt"); },
                         {"est.txt: the trajectory has no poses"}));
}

TEST(EvaluateTrajectory, FewerThanThreePairsAreAnErrorNamingBothFiles) {
  const Trajectory groundtruth = Helix(60);
  Trajectory estimate = groundtruth;
  for (size_t k = 2; k < estimate.size(); ++k) estimate[k].stamp += 100.0;  // only two stay paired
  EXPECT_THROW(EvaluateTrajectory(groundtruth, estimate, Config(), "gt.txt", "est.txt"), InputError);
  EXPECT_TRUE(ThrowsWith([&] { EvaluateTrajectory(groundtruth, estimate, Config(), "gt.txt", "est.txt"); },
                         {"est.txt: 2 of 60 poses lie within 0.020 s of a pose in gt.txt; need at least 3"}));
}

TEST(EvaluateTrajectory, ATrajectoryShorterThanTheRpeDeltaIsAnError) {
  const Trajectory groundtruth = Helix(20);  // 0.63 s
  EXPECT_TRUE(ThrowsWith([&] { EvaluateTrajectory(groundtruth, groundtruth, Config(1.0), "gt.txt", "est.txt"); },
                         {"est.txt: no two paired poses are 1.000 s apart", "the pairs span 0.633 s", "eval.rpe_delta"}));
  EXPECT_NO_THROW(EvaluateTrajectory(groundtruth, groundtruth, Config(0.5), "gt.txt", "est.txt"));
}

// --- Statistics --------------------------------------------------------------------------------

TEST(ErrorStats, MedianOfAnEvenCountIsTheMeanOfTheMiddleTwo) {
  const ErrorStats even = ComputeErrorStats({0.04, 0.01, 0.03, 0.02});  // [m]
  EXPECT_DOUBLE_EQ(even.median, 0.025);
  EXPECT_DOUBLE_EQ(even.mean, 0.025);
  EXPECT_DOUBLE_EQ(even.max, 0.04);
  EXPECT_DOUBLE_EQ(even.rmse, std::sqrt((0.0016 + 0.0001 + 0.0009 + 0.0004) / 4));
  EXPECT_DOUBLE_EQ(ComputeErrorStats({0.3, 0.1, 0.2}).median, 0.2);
  EXPECT_EQ(ComputeErrorStats({}).count, 0u);
}

}  // namespace
}  // namespace planemap
