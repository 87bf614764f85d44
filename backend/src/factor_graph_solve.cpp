// The rounds of a batch or window solve: the noise estimated from the residuals (variance
// component estimation), outliers dropped, and the problem solved again.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "factor_graph.h"
#include "noise_estimation.h"
#include "planemap/core/statistics.h"

namespace planemap::backend_detail {
namespace {

constexpr double kDegToRad = M_PI / 180.0;
// The redundancy's random probes: a fixed seed, so a run gives the same result every time.
constexpr uint32_t kProbeSeed = 1;

// A plane observation's tilt at the solution, along the eigenvectors of its fit's tilt
// covariance (2 components), each with its fit's variance, its floor and the fit's pixels.
NoiseSample TiltSample(const PlaneObservation& p, const Plane& in_camera, double floor_rad) {
  const Eigen::Vector3d n = p.plane.normal.normalized();
  const Eigen::Vector3d a = n.unitOrthogonal(), b = n.cross(a);  // PlaneObservationFactor's basis
  Eigen::Matrix2d fit;
  fit << a.dot(p.covariance.topLeftCorner<3, 3>() * a), a.dot(p.covariance.topLeftCorner<3, 3>() * b),
      b.dot(p.covariance.topLeftCorner<3, 3>() * a), b.dot(p.covariance.topLeftCorner<3, 3>() * b);
  const Eigen::Vector2d error(a.dot(in_camera.normal - n), b.dot(in_camera.normal - n));
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(fit);
  NoiseSample tilt;
  tilt.components = 2;
  tilt.pixels = p.inliers;
  for (int j = 0; j < 2; ++j) {
    tilt.squared[j] = std::pow(eig.eigenvectors().col(j).dot(error), 2);
    tilt.variance[j] = std::max(eig.eigenvalues()[j], 0.0);
    tilt.floor[j] = floor_rad * floor_rad;
  }
  return tilt;
}

}  // namespace

SolveReport FactorGraph::Solve() {
  ceres::Solver::Options options;
  options.linear_solver_type = SolverType(config_.linear_solver);
  options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  options.max_num_iterations = spec_.max_iterations;
  options.function_tolerance = config_.function_tolerance;
  options.num_threads = config_.threads;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem_, &summary);
  double initial_cost = summary.initial_cost, total_seconds = summary.total_time_in_seconds,
         minimizer_seconds = summary.minimizer_time_in_seconds;
  int iterations = static_cast<int>(summary.iterations.size()) - 1;  // the first entry is the start
  // Rounds: the noise estimated again from the residuals, then the observations off their
  // landmarks at the solution dropped (with the noise just estimated), and the problem solved
  // again, until neither changes anything.
  int outliers = 0, noise_rounds = 0, outlier_rounds = 0;
  while (summary.IsSolutionUsable()) {
    bool changed = false;
    if (spec_.estimate_noise && noise_rounds < config_.noise_rounds) {
      ++noise_rounds;
      const auto start = std::chrono::steady_clock::now();
      changed = UpdateNoise();
      total_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    if (spec_.drop_outliers && outlier_rounds < config_.outlier_rounds) {
      ++outlier_rounds;
      const int dropped = DropOutliers();
      outliers += dropped;
      changed = changed || dropped > 0;
    }
    if (!changed) break;
    ceres::Solve(options, &problem_, &summary);
    total_seconds += summary.total_time_in_seconds;
    minimizer_seconds += summary.minimizer_time_in_seconds;
    iterations += static_cast<int>(summary.iterations.size()) - 1;
  }
  SolveReport r;
  r.linear_solver = std::string(ceres::LinearSolverTypeToString(summary.linear_solver_type_used)) + " (" +
                    ceres::SparseLinearAlgebraLibraryTypeToString(options.sparse_linear_algebra_library_type) + ")";
  r.termination = std::string(ceres::TerminationTypeToString(summary.termination_type)) + ": " + summary.message;
  r.usable = summary.IsSolutionUsable();
  r.iterations = iterations;
  r.initial_cost = initial_cost;
  r.final_cost = summary.final_cost;
  r.seconds = total_seconds;
  r.seconds_per_iteration = iterations > 0 ? minimizer_seconds / iterations : 0.0;
  r.observations = static_cast<int>(observations_.size()) + outliers;
  r.outliers = outliers;
  r.poses = static_cast<int>(poses_.size());
  r.landmarks = static_cast<int>(landmarks_.size());
  r.cuboids = static_cast<int>(cuboids_.size());
  r.residual_blocks = summary.num_residual_blocks;
  r.brief = summary.BriefReport();
  r.full = noise_report_ + summary.FullReport();
  return r;
}

int FactorGraph::DropOutliers() {
  // Outliers: an observation that, at the solution, is not on its landmark (a wrong association
  // or a surface the landmark's one plane cannot hold) is dropped and the problem solved again.
  const double max_angle = config_.outlier_max_angle_deg * kDegToRad;
  std::vector<double> angles, distances;
  for (const Observed& o : observations_) {
    const Plane in_camera = TransformPlane(pose(o.pose).inverse(), WorldPlane(o.landmark));
    angles.push_back(std::acos(std::clamp(in_camera.normal.dot(o.observation->plane.normal), -1.0, 1.0)));
    distances.push_back(std::abs(in_camera.SignedDistance(o.observation->centroid)));
  }
  // The gates widen to outlier_spread_factor robust standard deviations of all the residuals
  // (1.4826 x their median) where the data are that far off as a whole.
  const double angle_gate = std::max(max_angle, config_.outlier_spread_factor * 1.4826 * Percentile(angles, 0.5));
  const double distance_gate = std::max(config_.outlier_max_distance, config_.outlier_spread_factor * 1.4826 * Percentile(distances, 0.5));
  std::vector<Observed> kept;
  for (size_t k = 0; k < observations_.size(); ++k) {
    const Observed& o = observations_[k];
    // Off by more than the gate and more than outlier_max_sigma of its own uncertainty (a far,
    // small plane's normal is only known to a degree or two).
    if (angles[k] > std::max(angle_gate, config_.outlier_max_sigma * o.normal_std) ||
        distances[k] > std::max(distance_gate, config_.outlier_max_sigma * o.offset_std)) {
      problem_.RemoveResidualBlock(o.block);
    } else {
      kept.push_back(o);
    }
  }
  const int dropped = static_cast<int>(observations_.size() - kept.size());
  if (dropped == 0) return 0;
  observations_ = std::move(kept);
  // A landmark all of whose observations went is no longer in the problem (its map plane stays).
  for (auto it = landmarks_.begin(); it != landmarks_.end();) {
    std::vector<ceres::ResidualBlockId> left;
    problem_.GetResidualBlocksForParameterBlock(it->second.data(), &left);
    if (left.empty()) {
      problem_.RemoveParameterBlock(it->second.data());
      it = landmarks_.erase(it);
    } else {
      ++it;
    }
  }
  return dropped;
}

bool FactorGraph::UpdateNoise() {
  // 1. The redundancy of each observation's tilt rows (the first two of PlaneObservationFactor's
  //    whitening). The tilts, not the shifts: on real frames the poses take up 60-90% of the
  //    shifts (three or four large planes fix a frame's translation), leaving too little of them
  //    to measure; the model ties the two (noise_estimation.h).
  std::vector<ResidualGroup> tilt_rows;
  for (const Observed& o : observations_) tilt_rows.push_back({{o.block}, 0, 2});
  const std::vector<double> redundancy = RedundancyFractions(&problem_, tilt_rows, config_.noise_probes, kProbeSeed);
  if (redundancy.empty()) return false;  // the information could not be factored: the noise stays
  // 2. Each observation's tilt at the solution, where its residual keeps enough of its error to
  //    tell, and the correlation that explains them.
  std::vector<NoiseSample> tilts;
  for (size_t k = 0; k < observations_.size(); ++k) {
    if (redundancy[k] < config_.noise_min_redundancy) continue;
    const Observed& o = observations_[k];
    tilts.push_back(TiltSample(*o.observation, TransformPlane(pose(o.pose).inverse(), WorldPlane(o.landmark)),
                               config_.plane_min_std_deg * kDegToRad));
    tilts.back().redundancy = redundancy[k];
  }
  if (tilts.size() < static_cast<size_t>(config_.noise_min_samples)) return false;
  const double next = EstimatePixelCorrelation(tilts);
  char line[200];
  std::snprintf(line, sizeof(line),
                "noise: %zu of %zu plane observations tell (redundancy %.2f at the median); the fits' pixels err together, as if %.0f "
                "of them were independent\n",
                tilts.size(), observations_.size(), Percentile(redundancy, 0.5), next > 0.0 ? 1.0 / next : INFINITY);
  noise_report_ += line;
  // 3. Whiten every observation anew when the estimate moved.
  if (std::abs(next - pixel_correlation_) <= config_.noise_tolerance * pixel_correlation_) return false;
  pixel_correlation_ = next;
  for (Observed& o : observations_) AddPlaneBlock(&o);
  return true;
}

}  // namespace planemap::backend_detail
