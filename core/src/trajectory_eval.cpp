#include "planemap/core/trajectory_eval.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include <Eigen/Geometry>

#include "planemap/core/error.h"

namespace planemap {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr size_t kMinPairs = 3;  // a rigid alignment needs three positions

std::string Seconds(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3f s", value);
  return buffer;
}

// Index of the stamp nearest to `target` in sorted `stamps` (not empty).
size_t NearestIndex(const std::vector<double>& stamps, double target) {
  const size_t after = std::lower_bound(stamps.begin(), stamps.end(), target) - stamps.begin();
  if (after == 0) return 0;
  if (after == stamps.size()) return after - 1;
  return target - stamps[after - 1] <= stamps[after] - target ? after - 1 : after;
}

}  // namespace

ErrorStats ComputeErrorStats(std::vector<double> errors) {
  ErrorStats stats;
  stats.count = errors.size();
  if (errors.empty()) return stats;
  std::sort(errors.begin(), errors.end());
  double sum = 0.0, sum_sq = 0.0;
  for (double e : errors) {
    sum += e;
    sum_sq += e * e;
  }
  const size_t n = errors.size();
  stats.rmse = std::sqrt(sum_sq / n);
  stats.mean = sum / n;
  stats.median = n % 2 == 1 ? errors[n / 2] : 0.5 * (errors[n / 2 - 1] + errors[n / 2]);
  stats.max = errors.back();
  return stats;
}

AssociatedPoses AssociatePoses(const Trajectory& groundtruth, const Trajectory& estimate, double max_time_gap) {
  std::vector<double> estimate_stamps(estimate.size()), groundtruth_stamps(groundtruth.size());
  for (size_t i = 0; i < estimate.size(); ++i) estimate_stamps[i] = estimate[i].stamp;
  for (size_t i = 0; i < groundtruth.size(); ++i) groundtruth_stamps[i] = groundtruth[i].stamp;
  auto pairs = AssociateStamps(estimate_stamps, groundtruth_stamps, max_time_gap);
  std::stable_sort(pairs.begin(), pairs.end(),
                   [&](const auto& a, const auto& b) { return estimate_stamps[a.first] < estimate_stamps[b.first]; });
  AssociatedPoses poses;
  for (const auto& [i, j] : pairs) {
    poses.stamps.push_back(estimate[i].stamp);
    poses.estimate.push_back(estimate[i].T_world_camera);
    poses.groundtruth.push_back(groundtruth[j].T_world_camera);
  }
  return poses;
}

AteResult ComputeAte(const AssociatedPoses& poses) {
  AteResult result;
  const size_t n = poses.size();
  if (n < kMinPairs) return result;
  Eigen::Matrix3Xd estimate(3, n), groundtruth(3, n);
  for (size_t i = 0; i < n; ++i) {
    estimate.col(i) = poses.estimate[i].translation();
    groundtruth.col(i) = poses.groundtruth[i].translation();
  }
  // Horn's closed form (as evaluate_ate.py): rigid, no scale.
  result.T_groundtruth_estimate.matrix() = Eigen::umeyama(estimate, groundtruth, /*with_scaling=*/false);
  std::vector<double> errors(n);
  for (size_t i = 0; i < n; ++i) {
    errors[i] = (result.T_groundtruth_estimate * estimate.col(i) - groundtruth.col(i)).norm();
  }
  result.translation = ComputeErrorStats(std::move(errors));
  return result;
}

RpeResult ComputeRpe(const AssociatedPoses& poses, double delta, double tolerance) {
  RpeResult result;
  result.delta = delta;
  std::vector<double> translation, rotation;
  for (size_t i = 0; i < poses.size(); ++i) {
    const double target = poses.stamps[i] + delta;
    const size_t j = NearestIndex(poses.stamps, target);
    if (j <= i || std::abs(poses.stamps[j] - target) > tolerance) continue;
    const Pose3 motion_groundtruth = poses.groundtruth[i].inverse() * poses.groundtruth[j];
    const Pose3 motion_estimate = poses.estimate[i].inverse() * poses.estimate[j];
    const Pose3 error = motion_groundtruth.inverse() * motion_estimate;
    translation.push_back(error.translation().norm());
    rotation.push_back(RotationAngle(error.linear()) * kRadToDeg);
  }
  result.translation = ComputeErrorStats(std::move(translation));
  result.rotation = ComputeErrorStats(std::move(rotation));
  return result;
}

TrajectoryEvaluation EvaluateTrajectory(const Trajectory& groundtruth, const Trajectory& estimate,
                                        const EvalConfig& config, const std::string& groundtruth_name,
                                        const std::string& estimate_name) {
  if (groundtruth.empty()) ThrowInputError(groundtruth_name, 0, "the trajectory has no poses");
  if (estimate.empty()) ThrowInputError(estimate_name, 0, "the trajectory has no poses");
  TrajectoryEvaluation result;
  result.groundtruth_poses = groundtruth.size();
  result.estimate_poses = estimate.size();
  const AssociatedPoses poses = AssociatePoses(groundtruth, estimate, config.max_time_gap);
  result.pairs = poses.size();
  if (poses.size() < kMinPairs) {
    ThrowInputError(estimate_name, 0,
                    std::to_string(poses.size()) + " of " + std::to_string(estimate.size()) + " poses lie within " +
                        Seconds(config.max_time_gap) + " of a pose in " + groundtruth_name + "; need at least " +
                        std::to_string(kMinPairs) + " (eval.max_time_gap)");
  }
  result.ate = ComputeAte(poses);
  result.T_groundtruth_estimate_first = poses.groundtruth.front() * poses.estimate.front().inverse();
  result.rpe = ComputeRpe(poses, config.rpe_delta, config.max_time_gap);
  if (result.rpe.translation.count == 0) {
    ThrowInputError(estimate_name, 0,
                    "no two paired poses are " + Seconds(config.rpe_delta) + " apart (within " +
                        Seconds(config.max_time_gap) + "); the pairs span " +
                        Seconds(poses.stamps.back() - poses.stamps.front()) + " (eval.rpe_delta)");
  }
  return result;
}

}  // namespace planemap
