// GCC 12 reports a false -Warray-bounds inside Eigen's SSE loads (Eigen::umeyama on floats, which
// PCL's ICP instantiates); it is silenced for the headers only, not for the code below them.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Warray-bounds"
#include "planemap/frontend/plane_registration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <pcl/filters/voxel_grid.h>
#include <pcl/registration/icp.h>
#pragma GCC diagnostic pop

namespace planemap {
namespace {

constexpr double kRadPerDeg = M_PI / 180.0;

// Singular values of the matrices with the unit normals as rows, source and target alike (the
// smaller of the two): below `smallest` the normals do not span 3-D, below `middle` too they are
// parallel. Whether the planes fix a pose is a matter of their directions only; the weights
// decide how precisely, not whether (a heavy floor does not make two walls parallel).
struct NormalSpread {
  double smallest = 0.0;
  double middle = 0.0;
};

NormalSpread ComputeSpread(const std::vector<PlaneCorrespondence>& correspondences) {
  Eigen::Matrix3d source = Eigen::Matrix3d::Zero(), target = Eigen::Matrix3d::Zero();
  for (const PlaneCorrespondence& c : correspondences) {
    source += c.source.normal * c.source.normal.transpose();
    target += c.target.normal * c.target.normal.transpose();
  }
  const Eigen::Vector3d s = NormalSingularValues(source), t = NormalSingularValues(target);
  return {std::min(s[0], t[0]), std::min(s[1], t[1])};
}

std::string FirstInvalid(const std::vector<PlaneCorrespondence>& correspondences) {
  for (size_t k = 0; k < correspondences.size(); ++k) {
    const PlaneCorrespondence& c = correspondences[k];
    const bool finite = c.source.normal.allFinite() && c.target.normal.allFinite() &&
                        std::isfinite(c.source.offset) && std::isfinite(c.target.offset);
    if (!finite || !(c.weight > 0.0 && std::isfinite(c.weight))) {
      return "correspondence " + std::to_string(k) + " has a non-finite plane or a weight that is not positive";
    }
  }
  return "";
}

// The consensus of one pose: which pairs it explains, and how well (errors over thresholds, squared).
struct Consensus {
  Pose3 T_target_source = Pose3::Identity();
  std::vector<int> inliers;
  double support = 0.0;   // sum of the inliers' weights
  double residual = 0.0;

  bool BetterThan(const Consensus& o) const {
    const double tolerance = 1e-9 * std::max(support, o.support);
    return support > o.support + tolerance || (std::abs(support - o.support) <= tolerance && residual < o.residual);
  }
};

Consensus Score(const Pose3& T_target_source, const std::vector<PlaneCorrespondence>& correspondences,
                const PlaneRansacConfig& config) {
  // Each pair's error over the thresholds; within a group only the best inlier counts.
  const double max_angle = config.inlier_angle_deg * kRadPerDeg;
  std::vector<std::pair<int, double>> chosen;  // (pair, error), one per group, in first-seen order
  std::vector<std::pair<int, size_t>> group_slot;
  for (size_t k = 0; k < correspondences.size(); ++k) {
    const PlaneCorrespondence& c = correspondences[k];
    const Plane predicted = TransformPlane(T_target_source, c.source);
    const double angle = NormalAngle(predicted, c.target);
    const double distance = c.source_point ? std::abs(c.target.SignedDistance(T_target_source * *c.source_point))
                                           : std::abs(predicted.offset - c.target.offset);
    if (angle > max_angle || distance > config.inlier_distance) continue;
    const double error = std::pow(angle / max_angle, 2) + std::pow(distance / config.inlier_distance, 2);
    auto slot = c.group < 0 ? group_slot.end()
                            : std::find_if(group_slot.begin(), group_slot.end(), [&](const auto& g) { return g.first == c.group; });
    if (slot == group_slot.end()) {
      if (c.group >= 0) group_slot.emplace_back(c.group, chosen.size());
      chosen.emplace_back(static_cast<int>(k), error);
    } else if (error < chosen[slot->second].second) {
      chosen[slot->second] = {static_cast<int>(k), error};
    }
  }
  Consensus consensus{T_target_source, {}, 0.0, 0.0};
  for (const auto& [k, error] : chosen) {
    consensus.inliers.push_back(k);
    consensus.support += correspondences[k].weight;
    consensus.residual += error;
  }
  std::sort(consensus.inliers.begin(), consensus.inliers.end());
  return consensus;
}

// Minimal samples: every triple for 3-4 pairs, else max_iterations random triples of distinct pairs.
std::vector<std::array<int, 3>> Samples(int n, const PlaneRansacConfig& config) {
  std::vector<std::array<int, 3>> samples;
  if (n <= 4) {
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        for (int k = j + 1; k < n; ++k) samples.push_back({i, j, k});
      }
    }
    return samples;
  }
  std::mt19937_64 rng(static_cast<std::uint64_t>(config.seed));
  const auto draw = [&] { return static_cast<int>(rng() % static_cast<std::uint64_t>(n)); };
  while (static_cast<int>(samples.size()) < config.max_iterations) {
    const std::array<int, 3> s = {draw(), draw(), draw()};
    if (s[0] != s[1] && s[0] != s[2] && s[1] != s[2]) samples.push_back(s);
  }
  return samples;
}

std::vector<PlaneCorrespondence> Select(const std::vector<PlaneCorrespondence>& all, const std::vector<int>& indices) {
  std::vector<PlaneCorrespondence> selected;
  for (int i : indices) selected.push_back(all[i]);
  return selected;
}

using PointNormalCloud = pcl::PointCloud<pcl::PointNormal>;

// Point-to-plane ICP (linearised least squares on the target normals) that needs 6 pairs for its
// 6 unknowns and tells how many iterations it ran (PCL keeps the count protected).
class PointToPlaneIcp : public pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> {
 public:
  PointToPlaneIcp() { min_number_correspondences_ = 6; }
  int Iterations() const { return nr_iterations_; }
};

// The finite points of `cloud`, voxel-downsampled when leaf > 0. A voxel's normal is the mean of
// its points' normals, made unit again.
PointNormalCloud::Ptr Prepare(const PointNormalCloud& cloud, double leaf) {
  auto finite = std::make_shared<PointNormalCloud>();
  for (const pcl::PointNormal& p : cloud) {
    if (p.getVector3fMap().allFinite() && p.getNormalVector3fMap().allFinite()) finite->push_back(p);
  }
  if (leaf <= 0.0) return finite;
  auto downsampled = std::make_shared<PointNormalCloud>();
  pcl::VoxelGrid<pcl::PointNormal> grid;
  grid.setInputCloud(finite);
  grid.setLeafSize(leaf, leaf, leaf);
  grid.filter(*downsampled);
  for (pcl::PointNormal& p : *downsampled) p.getNormalVector3fMap().normalize();
  return downsampled;
}

}  // namespace

Eigen::Matrix3d RotationFromCorrelation(const Eigen::Matrix3d& H) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixV() * D * svd.matrixU().transpose();
}

std::optional<Pose3> SolvePlaneToPlane(const std::vector<PlaneCorrespondence>& correspondences,
                                       double min_normal_spread, std::string* reason) {
  const auto fail = [&](const std::string& why) -> std::optional<Pose3> {
    if (reason) *reason = why;
    return std::nullopt;
  };
  if (correspondences.size() < 3) {
    return fail(std::to_string(correspondences.size()) +
                " plane correspondences: a pose needs at least 3 planes whose normals span 3-D");
  }
  if (const std::string invalid = FirstInvalid(correspondences); !invalid.empty()) return fail(invalid);
  const NormalSpread spread = ComputeSpread(correspondences);
  if (spread.smallest < min_normal_spread) {
    std::ostringstream why;
    why << "the normals do not span 3-D (smallest singular value " << spread.smallest << " < " << min_normal_spread
        << "): " << (spread.middle < min_normal_spread ? "the planes are parallel"
                                                       : "the normals are coplanar, e.g. a corridor's floor and walls");
    return fail(why.str());
  }
  // Rotation (weighted Kabsch): H = sum w n_s n_t^T = U S V^T maximises sum w n_t . (R n_s) at
  // R = V diag(1, 1, det(V U^T)) U^T. Translation: normal equations of w (n_t . t - (d_s - d_t))^2.
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero(), A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const PlaneCorrespondence& c : correspondences) {
    const Eigen::Vector3d& n_t = c.target.normal;
    H += c.weight * c.source.normal * n_t.transpose();
    A += c.weight * n_t * n_t.transpose();
    b += c.weight * n_t * (c.source.offset - c.target.offset);
  }
  Pose3 T_target_source = Pose3::Identity();
  T_target_source.linear() = RotationFromCorrelation(H);
  T_target_source.translation() = A.ldlt().solve(b);
  return T_target_source;
}

PlaneRansacResult EstimatePoseRansac(const std::vector<PlaneCorrespondence>& correspondences,
                                     const PlaneRansacConfig& config, const std::vector<Pose3>& hypotheses,
                                     const std::function<double(const Pose3&)>& plausibility) {
  ValidateConfig(config, "ransac.");
  PlaneRansacResult result;
  const int n = static_cast<int>(correspondences.size());
  if (n < 3) {
    result.reason = std::to_string(n) + " plane correspondences: RANSAC needs at least 3";
    return result;
  }
  // 1. Hypotheses from minimal samples [20]; 2. the one most pairs agree with, their support
  // scaled by the pose's plausibility (0: not considered).
  const auto scored = [&](const Pose3& T) -> std::optional<Consensus> {
    const double factor = plausibility ? plausibility(T) : 1.0;
    if (!(factor > 0.0)) return std::nullopt;
    Consensus consensus = Score(T, correspondences, config);
    consensus.support *= factor;
    return consensus;
  };
  std::optional<Consensus> best;
  for (const Pose3& T : hypotheses) {
    std::optional<Consensus> candidate = scored(T);
    if (candidate && (!best || candidate->BetterThan(*best))) best = std::move(candidate);
  }
  std::string degenerate;
  int inadmissible = 0;
  for (const std::array<int, 3>& s : Samples(n, config)) {
    const auto T = SolvePlaneToPlane(Select(correspondences, {s[0], s[1], s[2]}), config.min_normal_spread, &degenerate);
    if (!T) continue;
    std::optional<Consensus> candidate = scored(*T);
    if (!candidate) {
      ++inadmissible;
      continue;
    }
    if (!best || candidate->BetterThan(*best)) best = std::move(candidate);
  }
  if (!best) {
    result.reason = inadmissible > 0 ? "no admissible pose: " + std::to_string(inadmissible) + " samples gave poses ruled out"
                                     : "every sample of 3 plane correspondences was degenerate; last: " + degenerate;
    return result;
  }
  if (best->inliers.size() < 3) {
    result.reason = "no pose explains 3 or more plane correspondences (best: " + std::to_string(best->inliers.size()) + ")";
    return result;
  }
  // 3. Refit on all inliers; keep the sample's pose if the refit has less support (or if
  // heavier, parallel inliers make the weighted set degenerate).
  const auto T = config.refit ? SolvePlaneToPlane(Select(correspondences, best->inliers), config.min_normal_spread) : std::nullopt;
  if (T) {
    std::optional<Consensus> refit = scored(*T);
    if (refit && refit->support >= best->support) best = std::move(refit);
  }
  result.T_target_source = best->T_target_source;
  result.inliers = best->inliers;
  result.ok = true;
  return result;
}

PointToPlaneResult AlignPointsToPlanes(const std::vector<PointsOnPlane>& groups, const Pose3& initial,
                                       const Pose3& prior, double prior_weight, int max_iterations, double robust_scale) {
  using Matrix6d = Eigen::Matrix<double, 6, 6>;
  using Vector6d = Eigen::Matrix<double, 6, 1>;
  PointToPlaneResult result;
  result.T_target_source = initial;
  Pose3& T = result.T_target_source;
  for (int iteration = 0; iteration <= max_iterations; ++iteration) {
    // With q = T p and the left perturbation q' = q + theta x q + rho, a point's residual
    // r = n . q + d has the Jacobian a^T, a = (q x n, n) = A q + c with A = (-[n]x ; 0), c = (0 ; n).
    // Sums over a group's points need only its moments moved into frame t.
    Matrix6d H = Matrix6d::Zero();
    Vector6d g = Vector6d::Zero();
    double cost = 0.0, weight_sum = 0.0;
    for (const PointsOnPlane& group : groups) {
      if (group.source.w <= 0.0) continue;
      const PointMoments moved = TransformMoments(T, group.source);
      const Eigen::Vector3d& n = group.target.normal;
      const double d = group.target.offset;
      // Cauchy weight on the group's mean distance to its plane (point noise averages out of it;
      // a wrong pairing does not).
      const double mean_distance = n.dot(moved.Mean()) + d;
      const double robust = robust_scale > 0.0 ? 1.0 / (1.0 + std::pow(mean_distance / robust_scale, 2)) : 1.0;
      const double weight = group.weight * robust;
      const double W = weight * moved.w;
      const Eigen::Vector3d S = weight * moved.sum;        // sum w q
      const Eigen::Matrix3d Q = weight * moved.sum_outer;  // sum w q q^T
      Eigen::Matrix<double, 6, 3> A = Eigen::Matrix<double, 6, 3>::Zero();
      A.topRows<3>() << 0.0, n.z(), -n.y(), -n.z(), 0.0, n.x(), n.y(), -n.x(), 0.0;  // -[n]x
      Vector6d c = Vector6d::Zero();
      c.tail<3>() = n;
      H += A * Q * A.transpose() + A * S * c.transpose() + c * S.transpose() * A.transpose() + W * c * c.transpose();
      g += A * Q * n + d * A * S + c * n.dot(S) + d * W * c;
      cost += n.dot(Q * n) + 2.0 * d * n.dot(S) + d * d * W;
      weight_sum += W;
    }
    result.information = H;
    result.rms = weight_sum > 0.0 ? std::sqrt(std::max(0.0, cost) / weight_sum) : 0.0;
    result.iterations = iteration;
    if (iteration == max_iterations || weight_sum <= 0.0) break;
    // The prior: e = Log(T prior^-1) ~ e0 + delta for the left perturbation.
    const Vector6d e0 = RotationVectorAndTranslation(T * prior.inverse());
    const double scale = prior_weight * std::max(H.trace() / 6.0, 1e-12);
    const Matrix6d Hp = H + scale * Matrix6d::Identity();
    const Vector6d delta = -Hp.ldlt().solve(g + scale * e0);
    if (!delta.allFinite()) break;
    T = PoseFromRotationVectorAndTranslation(delta) * T;
    if (delta.head<3>().norm() < 1e-9 && delta.tail<3>().norm() < 1e-9) {
      result.iterations = iteration + 1;
      max_iterations = iteration + 1;  // one more pass evaluates H and the cost at the solution
    }
  }
  return result;
}

IcpResult RefineIcp(const pcl::PointCloud<pcl::PointNormal>& source, const pcl::PointCloud<pcl::PointNormal>& target,
                    const Pose3& initial_T_target_source, const IcpConfig& config) {
  ValidateConfig(config, "icp.");
  IcpResult result;
  result.T_target_source = initial_T_target_source;
  const PointNormalCloud::Ptr source_points = Prepare(source, config.voxel_size);
  const PointNormalCloud::Ptr target_points = Prepare(target, config.voxel_size);
  if (source_points->size() < 6 || target_points->size() < 6) {
    result.reason = "too few points for ICP: " + std::to_string(source_points->size()) + " source, " +
                    std::to_string(target_points->size()) + " target (at least 6 each)";
    return result;
  }
  PointToPlaneIcp icp;
  icp.setInputSource(source_points);
  icp.setInputTarget(target_points);
  icp.setMaximumIterations(config.max_iterations);
  icp.setMaxCorrespondenceDistance(config.max_correspondence_distance);
  icp.setTransformationEpsilon(config.transformation_epsilon);
  PointNormalCloud aligned;
  icp.align(aligned, initial_T_target_source.matrix().cast<float>());

  using Criteria = pcl::registration::DefaultConvergenceCriteria<float>;
  const Criteria::ConvergenceState state = icp.getConvergeCriteria()->getConvergenceState();
  result.iterations = icp.Iterations();
  if (state == Criteria::CONVERGENCE_CRITERIA_NO_CORRESPONDENCES) {
    result.reason = "fewer than 6 point pairs within max_correspondence_distance; kept the initial pose";
    return result;
  }
  result.converged = state == Criteria::CONVERGENCE_CRITERIA_TRANSFORM ||
                     state == Criteria::CONVERGENCE_CRITERIA_ABS_MSE || state == Criteria::CONVERGENCE_CRITERIA_REL_MSE;
  if (!result.converged) result.reason = "still moving after max_iterations (" + std::to_string(config.max_iterations) + ")";
  const Eigen::Matrix4d T = icp.getFinalTransformation().cast<double>();
  // Single precision drifts off orthonormal; the quaternion restores it.
  result.T_target_source = MakePose(Eigen::Quaterniond(Eigen::Matrix3d(T.topLeftCorner<3, 3>())), T.topRightCorner<3, 1>());
  result.fitness = icp.getFitnessScore(config.max_correspondence_distance);
  return result;
}

pcl::PointCloud<pcl::PointNormal>::Ptr PlanePoints(const DetectedPlane& plane, const Cloud& cloud, int stride) {
  if (stride < 1) throw std::invalid_argument("PlanePoints: stride must be >= 1, got " + std::to_string(stride));
  auto points = std::make_shared<PointNormalCloud>();
  const Eigen::Vector3d& n = plane.plane.normal;
  for (size_t k = 0; k < plane.inliers.size(); k += static_cast<size_t>(stride)) {
    const pcl::PointXYZRGB& p = cloud[plane.inliers[k]];
    if (!IsValidPoint(p)) continue;
    const Eigen::Vector3d x(p.x, p.y, p.z);
    pcl::PointNormal q;
    q.getVector3fMap() = (x - plane.plane.SignedDistance(x) * n).cast<float>();
    q.getNormalVector3fMap() = n.cast<float>();
    q.curvature = 0.0f;
    points->push_back(q);
  }
  return points;
}

bool IsSmallCorrection(const Pose3& correction, double max_translation, double max_rotation_deg) {
  return correction.translation().norm() < max_translation && RotationAngle(correction.linear()) < max_rotation_deg * M_PI / 180.0;
}

}  // namespace planemap
