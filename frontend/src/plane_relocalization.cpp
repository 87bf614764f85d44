#include "planemap/frontend/plane_relocalization.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>

#include <Eigen/Dense>

#include "planemap/frontend/plane_registration.h"

namespace planemap {
namespace {

constexpr double kRadPerDeg = M_PI / 180.0;

// Indices of the `count` heaviest planes, heaviest first (ties: lower index).
std::vector<int> Heaviest(const std::vector<RelocalizationPlane>& planes, int count) {
  std::vector<int> order(planes.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return planes[a].weight > planes[b].weight; });
  if (static_cast<int>(order.size()) > count) order.resize(count);
  return order;
}

double Angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::acos(std::clamp(a.dot(b), -1.0, 1.0)); }

// The rotation taking the source normals (a1, a2) onto the target normals (b1, b2): weighted
// Kabsch on the two normals and their cross product, so both pairs weigh alike.
Eigen::Matrix3d RotationFromTwoNormals(const Eigen::Vector3d& a1, const Eigen::Vector3d& a2, const Eigen::Vector3d& b1,
                                       const Eigen::Vector3d& b2) {
  const Eigen::Matrix3d H = a1 * b1.transpose() + a2 * b2.transpose() + a1.cross(a2).normalized() * b1.cross(b2).normalized().transpose();
  return RotationFromCorrelation(H);
}

struct RotationHypothesis {
  Eigen::Matrix3d R;
  double support = 0.0;
};

// Step 1: rotations from matched pairs of non-parallel normals, scored by the source weight whose
// normals they lay within inlier_angle_deg of some target normal; near-duplicates merged.
std::vector<RotationHypothesis> RotationHypotheses(const std::vector<RelocalizationPlane>& source,
                                                   const std::vector<RelocalizationPlane>& target,
                                                   const RelocalizationConfig& config) {
  const std::vector<int> s = Heaviest(source, config.max_source_planes), t = Heaviest(target, config.max_target_planes);
  const double min_angle = config.min_pair_angle_deg * kRadPerDeg, max_angle = M_PI - min_angle;
  const double tolerance = config.pair_angle_tolerance_deg * kRadPerDeg, inlier = config.inlier_angle_deg * kRadPerDeg;
  const auto support = [&](const Eigen::Matrix3d& R) {
    double sum = 0.0;
    for (const RelocalizationPlane& p : source) {
      const Eigen::Vector3d n = R * p.plane.normal;
      for (int k : t) {
        if (Angle(n, target[k].plane.normal) <= inlier) {
          sum += p.weight;
          break;
        }
      }
    }
    return sum;
  };
  std::vector<RotationHypothesis> all;
  for (size_t i = 0; i < s.size(); ++i) {
    for (size_t j = i + 1; j < s.size(); ++j) {
      const Eigen::Vector3d &a1 = source[s[i]].plane.normal, &a2 = source[s[j]].plane.normal;
      const double source_angle = Angle(a1, a2);
      if (source_angle < min_angle || source_angle > max_angle) continue;
      for (size_t k = 0; k < t.size(); ++k) {
        for (size_t l = 0; l < t.size(); ++l) {
          if (k == l) continue;  // both orders: (i, j) -> (k, l) and -> (l, k)
          const Eigen::Vector3d &b1 = target[t[k]].plane.normal, &b2 = target[t[l]].plane.normal;
          if (std::abs(Angle(b1, b2) - source_angle) > tolerance) continue;
          const Eigen::Matrix3d R = RotationFromTwoNormals(a1, a2, b1, b2);
          all.push_back({R, support(R)});
        }
      }
    }
  }
  std::stable_sort(all.begin(), all.end(), [](const RotationHypothesis& a, const RotationHypothesis& b) { return a.support > b.support; });
  std::vector<RotationHypothesis> kept;
  for (const RotationHypothesis& h : all) {
    if (static_cast<int>(kept.size()) >= config.max_rotations) break;
    const bool duplicate = std::any_of(kept.begin(), kept.end(), [&](const RotationHypothesis& k) {
      return RotationAngle(k.R.transpose() * h.R) < config.rotation_merge_deg * kRadPerDeg;
    });
    if (!duplicate) kept.push_back(h);
  }
  return kept;
}

// One source plane laid on one target plane by the rotation: n . t = b puts the source patch's
// centroid on the target plane.
struct Constraint {
  int source = -1, target = -1;
  Eigen::Vector3d normal;  // the target's [unit]
  double b = 0.0;          // [m]
};

// Step 2: the translation most source planes agree with under R, by RANSAC over triples of
// constraints; support counts each source plane once.
RelocalizationHypothesis BestTranslation(const Eigen::Matrix3d& R, const std::vector<RelocalizationPlane>& source,
                                         const std::vector<RelocalizationPlane>& target, const RelocalizationConfig& config,
                                         std::mt19937_64* rng) {
  std::vector<Constraint> constraints;
  const double inlier = config.inlier_angle_deg * kRadPerDeg;
  for (size_t i = 0; i < source.size(); ++i) {
    const Eigen::Vector3d n = R * source[i].plane.normal;
    for (size_t l = 0; l < target.size(); ++l) {
      const Plane& p = target[l].plane;
      if (Angle(n, p.normal) > inlier) continue;
      constraints.push_back({static_cast<int>(i), static_cast<int>(l), p.normal, -p.offset - p.normal.dot(R * source[i].centroid)});
    }
  }
  RelocalizationHypothesis best;
  const int n = static_cast<int>(constraints.size());
  if (n < 3) return best;
  // Which constraints a translation satisfies, one per source plane (the nearest), and their weight.
  const auto consensus = [&](const Eigen::Vector3d& t, std::vector<int>* chosen) {
    std::vector<double> error(source.size(), config.inlier_distance);
    chosen->assign(source.size(), -1);
    Pose3 T = Pose3::Identity();
    T.linear() = R;
    T.translation() = t;
    for (int k = 0; k < n; ++k) {
      const Constraint& c = constraints[k];
      const double e = std::abs(c.normal.dot(t) - c.b);
      if (e >= error[c.source]) continue;
      const Box3 placed = TransformBox(T, source[c.source].extent.low, source[c.source].extent.high);
      if (!placed.Overlaps(target[c.target].extent, config.overlap_margin)) continue;
      error[c.source] = e;
      (*chosen)[c.source] = k;
    }
    double sum = 0.0;
    for (size_t i = 0; i < source.size(); ++i) sum += (*chosen)[i] >= 0 ? source[i].weight : 0.0;
    return sum;
  };
  std::vector<int> chosen;
  for (int sample = 0; sample < config.translation_samples; ++sample) {
    const std::array<int, 3> k = {static_cast<int>((*rng)() % n), static_cast<int>((*rng)() % n), static_cast<int>((*rng)() % n)};
    Eigen::Matrix3d A;
    Eigen::Vector3d b;
    for (int r = 0; r < 3; ++r) {
      A.row(r) = constraints[k[r]].normal.transpose();
      b[r] = constraints[k[r]].b;
    }
    if (NormalSingularValues(A.transpose() * A)[0] < config.min_normal_spread) continue;  // also: a repeated constraint
    const Eigen::Vector3d t = A.partialPivLu().solve(b);
    const double support = consensus(t, &chosen);
    if (support <= best.support) continue;
    // Least squares over the agreeing constraints; kept only if their normals fix all of t.
    Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Atb = Eigen::Vector3d::Zero();
    int planes = 0;
    for (int c : chosen) {
      if (c < 0) continue;
      AtA += constraints[c].normal * constraints[c].normal.transpose();
      Atb += constraints[c].normal * constraints[c].b;
      ++planes;
    }
    if (NormalSingularValues(AtA)[0] < config.min_normal_spread) continue;
    best.T_target_source.linear() = R;
    best.T_target_source.translation() = AtA.ldlt().solve(Atb);
    best.support = support;
    best.planes = planes;
  }
  return best;
}

}  // namespace

std::vector<RelocalizationHypothesis> RelocalizeByPlanes(const std::vector<RelocalizationPlane>& source,
                                                         const std::vector<RelocalizationPlane>& target,
                                                         const RelocalizationConfig& config) {
  ValidateConfig(config, "relocalization.");
  std::mt19937_64 rng(static_cast<std::uint64_t>(config.seed));
  std::vector<RelocalizationHypothesis> poses;
  for (const RotationHypothesis& r : RotationHypotheses(source, target, config)) {
    RelocalizationHypothesis h = BestTranslation(r.R, source, target, config, &rng);
    if (h.planes >= 3) poses.push_back(h);
  }
  std::stable_sort(poses.begin(), poses.end(),
                   [](const RelocalizationHypothesis& a, const RelocalizationHypothesis& b) { return a.support > b.support; });
  std::vector<RelocalizationHypothesis> kept;
  for (const RelocalizationHypothesis& h : poses) {
    if (static_cast<int>(kept.size()) >= config.max_hypotheses) break;
    const bool duplicate = std::any_of(kept.begin(), kept.end(), [&](const RelocalizationHypothesis& k) {
      const Pose3 d = k.T_target_source.inverse() * h.T_target_source;
      return RotationAngle(d.linear()) < config.rotation_merge_deg * kRadPerDeg && d.translation().norm() < config.inlier_distance;
    });
    if (!duplicate) kept.push_back(h);
  }
  return kept;
}

}  // namespace planemap
