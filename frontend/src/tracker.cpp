#include "planemap/frontend/tracker.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <stdexcept>
#include <utility>

#include <Eigen/Dense>

#include "planemap/frontend/silhouette.h"

namespace planemap {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// The projector onto the directions no normal of `normals` (sum of n n^T) fixes: those along
// which its square root's eigenvalue is under min_spread.
Eigen::Matrix3d FreeDirections(const Eigen::Matrix3d& normals, double min_spread) {
  Eigen::Matrix3d free = Eigen::Matrix3d::Zero();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(normals);
  for (int k = 0; k < 3; ++k) {
    if (std::sqrt(std::max(0.0, eigen.eigenvalues()[k])) < min_spread) {
      free += eigen.eigenvectors().col(k) * eigen.eigenvectors().col(k).transpose();
    }
  }
  return free;
}

}  // namespace

const char* ToString(TrackStatus status) {
  switch (status) {
    case TrackStatus::kTracked: return "tracked";
    case TrackStatus::kDegraded: return "degraded";
    case TrackStatus::kLost: return "lost";
  }
  return "?";
}

// A frame plane as the tracker uses it: camera-frame plane, inlier moments and box, and its
// world form under the current pose estimate.
struct Tracker::Observation {
  int plane = -1;                 // id in the frame model
  Plane camera;
  PointMoments moments;           // its inliers, camera frame, weighted by DepthNoiseWeight
  Eigen::Vector3d centroid_c = Eigen::Vector3d::Zero();  // mean of its inliers, camera frame [m]
  Eigen::Vector3d low_c = Eigen::Vector3d::Zero(), high_c = Eigen::Vector3d::Zero();  // inlier box, camera frame [m]
  Plane world;
  Eigen::Vector3d centroid_w = Eigen::Vector3d::Zero();  // [m]
  // That box's corners moved into the world, boxed again [m].
  Eigen::Vector3d low_w = Eigen::Vector3d::Zero(), high_w = Eigen::Vector3d::Zero();
  int inliers = 0;

  // Its weight among the frame's planes: a plane's offset error grows with its depth's noise
  // (z^2) and shrinks with its inliers, but only as their square root, as depth errors are
  // correlated (steps, a bend).
  double Weight() const {
    const double z = std::max(centroid_c.z(), 0.5);
    return std::sqrt(static_cast<double>(inliers)) / (z * z);
  }

  void Place(const Pose3& T_world_camera) {
    world = TransformPlane(T_world_camera, camera);
    centroid_w = T_world_camera * centroid_c;
    const Box3 box = TransformBox(T_world_camera, low_c, high_c);
    low_w = box.low;
    high_w = box.high;
  }
};

Tracker::Tracker(const TrackingConfig& config, const Pose3& T_world_first) : config_(config), T_world_first_(T_world_first) {
  ValidateConfig(config_, "tracking.");  // ranges, and refine is points, icp or none
}

Tracker::Tracker(const TrackingConfig& config, const Pose3& T_world_first, const CameraIntrinsics& camera)
    : Tracker(config, T_world_first) {
  camera_ = camera;
}

double Tracker::SeeThroughFraction(const Pose3& T_world_camera, const Cloud& cloud) const {
  if (!camera_ || static_cast<int>(cloud.width) != camera_->width || static_cast<int>(cloud.height) != camera_->height) return -1.0;
  // Every landmark's stored surface points that face the camera, at most about 4000 of them.
  size_t total = 0;
  for (const PlaneLandmark& l : map_.landmarks) total += l.points.size();
  const size_t step = std::max<size_t>(1, total / 4000);
  const Pose3 T_camera_world = T_world_camera.inverse();
  const Eigen::Vector3d eye = T_world_camera.translation();
  int seen = 0, through = 0;
  size_t k = 0;
  for (const PlaneLandmark& l : map_.landmarks) {
    for (const Eigen::Vector3f& point : l.points) {
      if (k++ % step != 0) continue;
      const Eigen::Vector3d p = point.cast<double>();
      if (l.plane.normal.dot(eye - p) <= 0.0) continue;  // its back: the camera cannot see this side
      const Eigen::Vector3d c = T_camera_world * p;
      if (c.z() < 0.3 || c.z() > config_.max_depth) continue;
      const Eigen::Vector2d uv = camera_->Project(c);
      const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
      if (u < 0 || v < 0 || u >= camera_->width || v >= camera_->height) continue;
      // The measured depths at the pixel and around it (relocalize_edge_px away): a point at a
      // silhouette is not seen through when a slightly different pose would put it on its surface.
      const double tolerance = config_.relocalize_depth_tolerance + config_.relocalize_depth_tolerance_per_m * c.z();
      const int r = config_.relocalize_edge_px;
      bool measured_any = false, beyond = true;
      for (const auto& [du, dv] : {std::pair{0, 0}, {-r, 0}, {r, 0}, {0, -r}, {0, r}}) {
        const int x = u + du, y = v + dv;
        if (x < 0 || y < 0 || x >= camera_->width || y >= camera_->height) continue;
        const float measured = cloud.at(x, y).z;
        if (!std::isfinite(measured)) continue;
        measured_any = true;
        beyond = beyond && measured > c.z() + tolerance;
      }
      const float measured = cloud.at(u, v).z;
      if (!measured_any || (std::isfinite(measured) && measured < c.z() - tolerance)) continue;  // something in front: no verdict
      ++seen;
      through += beyond;
    }
  }
  return seen >= config_.relocalize_min_checked_points ? static_cast<double>(through) / seen : -1.0;
}

Pose3 Tracker::Predict(double stamp, const std::optional<Pose3>& T_odometry_camera) const {
  if (history_.empty()) return T_world_first_;
  const auto& [t1, T1] = history_.back();
  // Odometry: its motion since the last accepted pose, in that pose's camera frame.
  if (T_odometry_camera && odometry_at_last_) return T1 * (odometry_at_last_->inverse() * *T_odometry_camera);
  if (history_.size() < 2) return T1;
  // Constant velocity over the window: the mean motion per second since its oldest pose,
  // applied in the camera frame for the time since the last tracked pose.
  const auto& [t0, T0] = history_.front();
  if (t1 - t0 <= 1e-6) return T1;
  const Eigen::Matrix<double, 6, 1> xi = RotationVectorAndTranslation(T0.inverse() * T1) / (t1 - t0);
  return T1 * PoseFromRotationVectorAndTranslation(xi * (stamp - t1));
}

std::vector<Tracker::Candidate> Tracker::Associate(const std::vector<Observation>& observed, double max_angle_deg,
                                                   double max_distance, int per_plane, double drift) const {
  // Gates: normals within max_angle, the patch's centroid within max_distance of the landmark's
  // plane (measured where the patch is, so a far plane's normal error is not magnified by its
  // distance from the world origin), extents that overlap. Several frame planes may take one
  // landmark (a surface the segmenter split in two).
  std::vector<Candidate> candidates;
  const double max_angle = max_angle_deg * kDegToRad;
  for (size_t i = 0; i < observed.size(); ++i) {
    std::vector<Candidate> mine;
    for (const PlaneLandmark& l : map_.landmarks) {
      // The prediction may be off by `drift` along the unobserved directions: as far as the
      // landmark's normal points along them, its distance gate widens.
      const double gate = max_distance + drift * (unobserved_ * l.plane.normal).norm();
      const double angle = NormalAngle(observed[i].world, l.plane);
      const double distance = std::abs(l.plane.SignedDistance(observed[i].centroid_w));
      if (angle > max_angle || distance > gate) continue;
      if (!l.Overlaps(observed[i].low_w, observed[i].high_w, config_.association.overlap_margin + drift)) continue;
      mine.push_back({static_cast<int>(i), l.id, angle / max_angle + distance / gate});
    }
    std::sort(mine.begin(), mine.end(), [](const Candidate& a, const Candidate& b) {
      return a.score < b.score || (a.score == b.score && a.landmark < b.landmark);
    });
    if (static_cast<int>(mine.size()) > per_plane) mine.resize(per_plane);
    candidates.insert(candidates.end(), mine.begin(), mine.end());
  }
  return candidates;
}

std::vector<int> Tracker::LandmarkOfPlane(const FrameModel& model, const std::vector<Observation>& observed,
                                          const std::vector<int>& landmark_of) {
  std::vector<int> landmark_of_plane(model.planes.size(), -1);
  for (size_t i = 0; i < observed.size(); ++i) landmark_of_plane[observed[i].plane] = std::max(-1, landmark_of[i]);
  return landmark_of_plane;
}

std::vector<PointsOnPlane> Tracker::SilhouetteGroups(const FrameModel& model, const Cloud& cloud,
                                                     const std::vector<Observation>& observed,
                                                     const std::vector<int>& landmark_of,
                                                     const Pose3& T) const {
  std::vector<PointsOnPlane> groups;
  const double max_dot = std::cos(80.0 * kDegToRad);  // a side is perpendicular to the face
  for (size_t i = 0; i < observed.size(); ++i) {
    if (landmark_of[i] < 0) continue;
    const auto object = std::find_if(map_.objects.begin(), map_.objects.end(), [&](const MapObject& o) {
      return !o.structure && std::count(o.landmarks.begin(), o.landmarks.end(), landmark_of[i]) > 0;
    });
    if (object == map_.objects.end()) continue;
    // The cuboid's sides next to this face, outward normals, where its dimension is whole.
    std::vector<Plane> sides;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d axis = object->axes.col(k);
      if (!object->dimension_complete[k] || std::abs(axis.dot(observed[i].world.normal)) > max_dot) continue;
      for (double sign : {1.0, -1.0}) {
        const Eigen::Vector3d n = sign * axis;
        sides.push_back({n, -n.dot(object->center + 0.5 * object->dimensions[k] * n)});
      }
    }
    if (sides.empty()) continue;
    // Per side, its pixels (camera frame) and their signed distances to it at T.
    std::vector<std::vector<std::pair<Eigen::Vector3d, double>>> on_side(sides.size());
    for (int p : SilhouettePixels(cloud, model.planes[observed[i].plane].inliers, config_.silhouette_min_gap,
                                  config_.silhouette_max_missing)) {
      const Eigen::Vector3d x = cloud[p].getVector3fMap().cast<double>();
      const Eigen::Vector3d xw = T * x;
      int best = -1;
      double nearest = config_.silhouette_max_distance, signed_distance = 0.0;
      for (size_t j = 0; j < sides.size(); ++j) {
        const double d = sides[j].SignedDistance(xw);
        if (std::abs(d) <= nearest) {
          nearest = std::abs(d);
          signed_distance = d;
          best = static_cast<int>(j);
        }
      }
      if (best >= 0) on_side[best].emplace_back(x, signed_distance);
    }
    for (size_t j = 0; j < sides.size(); ++j) {
      if (static_cast<int>(on_side[j].size()) < config_.silhouette_min_points) continue;
      double sum = 0.0, sum_sq = 0.0;
      PointMoments moments;
      for (const auto& [x, d] : on_side[j]) {
        sum += d;
        sum_sq += d * d;
        moments.Add(x, DepthNoiseWeight(x.z()));
      }
      const double n = static_cast<double>(on_side[j].size());
      const double spread_sq = sum_sq / n - (sum / n) * (sum / n);
      if (spread_sq > config_.silhouette_max_spread * config_.silhouette_max_spread) continue;
      groups.push_back({moments, sides[j], 1.0});
    }
  }
  return groups;
}

std::vector<PlaneCorrespondence> Tracker::Correspondences(const std::vector<Candidate>& candidates,
                                                          const std::vector<Observation>& observed) const {
  std::vector<PlaneCorrespondence> correspondences;
  for (const Candidate& c : candidates) {
    const Observation& o = observed[c.observation];
    // A landmark seen in fewer than confirm_views frames weighs in proportion (Confirmed).
    const PlaneLandmark& l = map_.landmarks[c.landmark];
    correspondences.push_back({o.camera, l.plane, Confirmed(l) * o.Weight(), o.centroid_c, c.observation});
  }
  // Weights relative to the best plane's, so the solver's spread test sees unit-scale rows.
  double max_weight = 0.0;
  for (const PlaneCorrespondence& c : correspondences) max_weight = std::max(max_weight, c.weight);
  for (PlaneCorrespondence& c : correspondences) c.weight /= max_weight;
  return correspondences;
}

double Tracker::SupportFraction(const PlaneRansacResult& ransac, const std::vector<Candidate>& candidates,
                                const std::vector<Observation>& observed) {
  double agreeing = 0.0, all = 0.0;
  for (int k : ransac.inliers) agreeing += observed[candidates[k].observation].Weight();
  for (const Observation& o : observed) all += o.Weight();
  return all > 0.0 ? agreeing / all : 0.0;
}

std::vector<RelocalizationHypothesis> Tracker::Relocalize(const std::vector<Observation>& observed) const {
  // The frame's planes (camera) against every landmark (world), weighted as in RANSAC: a
  // landmark by its confirmation and its mean patch size per view.
  std::vector<RelocalizationPlane> source, target;
  for (const Observation& o : observed) source.push_back({o.camera, o.centroid_c, {o.low_c, o.high_c}, o.Weight()});
  for (const PlaneLandmark& l : map_.landmarks) {
    if (l.observations <= 0 || l.moments.w <= 0.0) continue;
    const double weight = Confirmed(l) * std::sqrt(l.moments.n / l.observations);
    target.push_back({l.plane, l.moments.Mean(), {l.low, l.high}, weight});
  }
  return RelocalizeByPlanes(source, target, config_.relocalization);
}

double Tracker::Confirmed(const PlaneLandmark& l) const {
  return std::min(1.0, static_cast<double>(l.observations) / config_.confirm_views);
}

bool Tracker::Agrees(const Observation& o, const Plane& landmark) const {
  return NormalAngle(o.world, landmark) <= config_.merge_max_angle_deg * kDegToRad &&
         std::abs(landmark.SignedDistance(o.centroid_w)) <= config_.merge_max_distance;
}

std::optional<Tracker::Motion> Tracker::UnmeasuredMotion(const std::optional<Pose3>& T_odometry_camera) const {
  if (!T_odometry_camera || !odometry_at_rotation_) return std::nullopt;
  const Pose3 motion = odometry_at_rotation_->inverse() * *T_odometry_camera;
  return Motion{RotationAngle(motion.linear()) / kDegToRad, motion.translation().norm()};
}

bool Tracker::IsStructure(int landmark) const {
  return map_.landmarks[landmark].Extent() > config_.structure_min_extent;
}

std::optional<Eigen::Matrix3d> Tracker::SolveRotation(
    const std::vector<Candidate>& candidates, const std::vector<Observation>& observed, const Eigen::Matrix3d& predicted,
    const std::function<double(const Eigen::Matrix3d&)>& plausibility, std::vector<bool>* agreeing) const {
  // Each plane's best candidate: its camera normal, its landmark's world normal and its weight.
  struct Pair {
    Eigen::Vector3d camera, world;
    double weight;
    int observation;
  };
  std::vector<Pair> pairs;
  int last = -1;
  for (const Candidate& c : candidates) {  // best first within each plane
    if (c.observation == last) continue;
    last = c.observation;
    pairs.push_back({observed[c.observation].camera.normal, map_.landmarks[c.landmark].plane.normal,
                     std::sqrt(static_cast<double>(observed[c.observation].inliers)), c.observation});
  }
  // Weighted Kabsch on the normals (camera -> world) of the pairs `use` selects; none when they
  // span fewer than two directions.
  const auto solve = [&](const std::vector<bool>& use) -> std::optional<Eigen::Matrix3d> {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero(), spread = Eigen::Matrix3d::Zero();
    for (size_t k = 0; k < pairs.size(); ++k) {
      if (!use[k]) continue;
      H += pairs[k].weight * pairs[k].camera * pairs[k].world.transpose();
      spread += pairs[k].world * pairs[k].world.transpose();
    }
    if (NormalSingularValues(spread)[1] < config_.ransac.min_normal_spread) return std::nullopt;
    return RotationFromCorrelation(H);
  };
  // The pairs a rotation places within merge_max_angle_deg of their landmark, and their weight
  // times the rotation's plausibility.
  const double max_angle = config_.merge_max_angle_deg * kDegToRad;
  const auto support = [&](const Eigen::Matrix3d& R, std::vector<bool>* agree) {
    double score = 0.0;
    for (size_t k = 0; k < pairs.size(); ++k) {
      (*agree)[k] = std::acos(std::clamp((R * pairs[k].camera).dot(pairs[k].world), -1.0, 1.0)) <= max_angle;
      if ((*agree)[k]) score += pairs[k].weight;
    }
    return score * plausibility(R);
  };
  // Hypotheses: the prediction's rotation and the one from every two non-parallel planes. Not all
  // planes' normals together: a locker's side 3.6 m away at a glancing angle, a sliver at the
  // image's corner whose normal came out 3-19 deg off from frame to frame, pulled a standing
  // robot's heading 4.6 deg off what its floor and the box face before it said, and the map
  // followed (configs/scenes/gallery.yaml, seed 13).
  std::vector<bool> best_agree(pairs.size(), false), agree(pairs.size(), false);
  double best = support(predicted, &best_agree);
  for (size_t i = 0; i < pairs.size(); ++i) {
    for (size_t j = i + 1; j < pairs.size(); ++j) {
      std::vector<bool> use(pairs.size(), false);
      use[i] = use[j] = true;
      const std::optional<Eigen::Matrix3d> R = solve(use);
      if (!R) continue;
      const double score = support(*R, &agree);
      if (score > best) {
        best = score;
        best_agree = agree;
      }
    }
  }
  agreeing->assign(observed.size(), false);
  for (size_t k = 0; k < pairs.size(); ++k) (*agreeing)[pairs[k].observation] = best_agree[k];
  return best > 0.0 ? solve(best_agree) : std::nullopt;
}

TrackResult Tracker::Track(const FrameModel& model, const Cloud& cloud, double stamp,
                           const std::optional<Pose3>& T_odometry_camera) {
  const int frame = frame_++;
  TrackResult result;
  // The frame's planes large and near enough to track, with their inlier moments and boxes.
  std::vector<Observation> observed;
  const double max_normal_variance =
      std::pow(config_.max_normal_std_deg * kDegToRad, 2) / config_.correlated_pixels;
  for (const DetectedPlane& p : model.planes) {
    if (p.strip || static_cast<int>(p.inliers.size()) < config_.min_landmark_inliers || p.centroid.z() > config_.max_depth) continue;
    if (p.covariance.topLeftCorner<3, 3>().trace() > max_normal_variance) continue;  // see max_normal_std_deg
    Observation o;
    o.plane = p.id;
    o.camera = p.plane;
    o.inliers = static_cast<int>(p.inliers.size());
    o.centroid_c = p.centroid;
    o.low_c = Eigen::Vector3d::Constant(1e30);
    o.high_c = -o.low_c;
    for (int index : p.inliers) {
      const Eigen::Vector3d x = cloud[index].getVector3fMap().cast<double>();
      o.moments.Add(x, DepthNoiseWeight(x.z()));
      o.low_c = o.low_c.cwiseMin(x);
      o.high_c = o.high_c.cwiseMax(x);
    }
    observed.push_back(o);
  }
  result.planes = static_cast<int>(observed.size());

  const Pose3 predicted = Predict(stamp, T_odometry_camera);
  const bool odometry = T_odometry_camera && odometry_at_last_;  // the prediction is the odometry's
  // With odometry the heading errs by odometry_sigma_deg from the last pose, and more the more the
  // robot turned and walked since its rotation was last measured (a gait's turn comes out a few
  // per cent short or long, and every step drifts its heading a little).
  double heading_sigma_deg = config_.odometry_sigma_deg;
  if (const auto unmeasured = UnmeasuredMotion(T_odometry_camera)) {
    heading_sigma_deg += config_.odometry_turn_heading_error * unmeasured->turn_deg +
                         config_.odometry_walk_heading_error_deg * unmeasured->walked;
  }
  result.T_predicted = predicted;
  Pose3 T = predicted;
  Pose3 prior = predicted;  // what the refinement falls back on where no plane fixes the pose
  std::vector<int> landmark_of(observed.size(), -1);
  const bool first = map_.landmarks.empty() && history_.empty();
  std::vector<bool> rotation_agrees;  // degraded, with a solved rotation: per observation, whether it agreed
  const AssociationConfig& gates = config_.association;
  if (first) {
    T = T_world_first_;
  } else {
    // 1. Candidate pairs within wide gates of the prediction; RANSAC finds the pose most agree with.
    // Since the last fully tracked frame the prediction's unobserved directions may have drifted
    // by up to max_speed per second: the gates widen by as much, every landmark becomes a
    // candidate, and RANSAC draws more samples, so tracking recovers when structure returns.
    const double drift = unobserved_.trace() > 0.5 ? config_.max_speed * std::max(0.0, stamp - last_tracked_stamp_) : 0.0;
    for (Observation& o : observed) o.Place(predicted);
    std::vector<Candidate> candidates =
        Associate(observed, gates.search_angle_deg, gates.search_distance,
                  drift > 0.0 ? static_cast<int>(map_.landmarks.size()) : gates.max_candidates, drift);
    std::vector<PlaneCorrespondence> correspondences = Correspondences(candidates, observed);
    // Poses the robot cannot have reached from the prediction (beyond max_correction, plus the
    // drift along unobserved directions) are not hypotheses: parallel planes (a floor and a box
    // top, a shelf's boards) would otherwise offer consistent false matches.
    // With one pose behind it and no odometry the motion model knows no velocity yet: the robot
    // may have moved by up to max_speed since (a study's second frame, 10 cm on).
    const double unknown_motion =
        history_.size() == 1 && !odometry ? config_.max_speed * std::max(0.0, stamp - history_.back().first) : 0.0;
    // How much farther than max_correction(_deg) a pose may lie: only a relocalized one (below).
    double slack = 0.0, slack_angle = 0.0;  // [m], [rad]
    std::vector<Pose3> refused_poses;       // relocalized poses the depth refuted
    const auto plausibility = [&](const Pose3& T_candidate) {
      const Pose3 correction = predicted.inverse() * T_candidate;
      const Eigen::Vector3d moved = T_candidate.translation() - predicted.translation();  // world
      const Eigen::Vector3d along_unobserved = unobserved_ * moved;
      const double observed_part = (moved - along_unobserved).norm() / (config_.max_correction + unknown_motion + slack);
      const double unobserved_part = along_unobserved.norm() / (config_.max_correction + drift + slack);
      const double turn = RotationAngle(correction.linear()) / (config_.max_correction_deg * kDegToRad + slack_angle);
      if (observed_part > 1.0 || unobserved_part > 1.0 || turn > 1.0) return 0.0;
      for (const Pose3& refused : refused_poses) {
        const Pose3 d = refused.inverse() * T_candidate;
        if (d.translation().norm() < config_.relocalization.inlier_distance &&
            RotationAngle(d.linear()) < config_.relocalization.rotation_merge_deg * kDegToRad) {
          return 0.0;
        }
      }
      // Relocalizing, poses agreed with alike (a room's walls, a quarter turn apart) are told apart
      // by how far they lie from the prediction: the nearer weighs a little more.
      if (!odometry && (slack > 0.0 || slack_angle > 0.0)) {
        return 1.0 / (1.0 + config_.relocalize_tie_break * (observed_part * observed_part + turn * turn));
      }
      if (!odometry) return 1.0;
      // With odometry the prediction errs by about odometry_sigma (odometry_sigma_deg): support
      // is weighed by a Cauchy likelihood of the correction, so a pose as consistent as the
      // prediction's with fewer, lighter planes, but a few centimetres off it, is not taken.
      const double a = (moved - along_unobserved).norm() / config_.odometry_sigma;
      const double b = along_unobserved.norm() / (config_.odometry_sigma + drift);
      const double c = RotationAngle(correction.linear()) / (heading_sigma_deg * kDegToRad);
      return 1.0 / (1.0 + a * a + b * b + c * c);
    };
    const auto reachable = [&](const Pose3& T_candidate) { return plausibility(T_candidate) > 0.0; };
    PlaneRansacConfig ransac_config = config_.ransac;
    if (drift > 0.0) ransac_config.max_iterations = std::max(ransac_config.max_iterations, config_.recovery_iterations);
    PlaneRansacResult ransac = EstimatePoseRansac(correspondences, ransac_config, {predicted}, plausibility);
    // The winner may be the prediction (a hypothesis no degeneracy test applies to) agreed with
    // only by planes that fix fewer than 3 directions (a floor, a wall and planes parallel to
    // them): the direction they leave free is then the motion model's, not measured. Such a
    // frame is degraded, not tracked: it solves what its planes fix, and the free direction's
    // drift widens the gates so that the planes which fix it are found again.
    const auto fixes_three_directions = [&](PlaneRansacResult* r, const std::vector<Candidate>& pairs) {
      if (!r->ok) return;
      Eigen::Matrix3d normals = Eigen::Matrix3d::Zero();
      for (int k : r->inliers) {
        const Eigen::Vector3d& n = map_.landmarks[pairs[k].landmark].plane.normal;
        normals += n * n.transpose();
      }
      if (NormalSingularValues(normals)[0] < config_.ransac.min_normal_spread) {
        r->ok = false;
        r->reason = "the " + std::to_string(r->inliers.size()) + " planes that agree with the best pose do not fix 3 directions";
      }
    };
    fixes_three_directions(&ransac, candidates);
    // Three plane pairs whose normals span 3-D agree with the pose they give, right or wrong: a pose
    // is evidence when more planes agree with it, or when those three are most of what the frame
    // sees (a room's floor and two walls). In clutter (a desk's papers, books and monitor, 15-20
    // planes a frame) a three-plane consensus was often a wrong pairing of parallel surfaces.
    const auto enough_evidence = [&](PlaneRansacResult* r, const std::vector<Candidate>& pairs) {
      if (!r->ok || static_cast<int>(r->inliers.size()) >= config_.min_agreeing_planes ||
          SupportFraction(*r, pairs, observed) >= config_.min_agreeing_fraction) {
        return;
      }
      r->ok = false;
      r->reason = "only " + std::to_string(r->inliers.size()) + " of " + std::to_string(observed.size()) + " planes agree with the best pose";
    };
    enough_evidence(&ransac, candidates);
    // The share of the map's surfaces in view that a RANSAC pose, refined on its inliers' points,
    // sees through (the closed form of three planes may be a degree off, enough to move the map's
    // silhouettes over what the camera measures); negative: no verdict.
    const auto SeeThrough = [&](const PlaneRansacResult& r, const std::vector<Candidate>& pairs) {
      std::vector<PointsOnPlane> inlier_points;
      for (int k : r.inliers) inlier_points.push_back({observed[pairs[k].observation].moments, map_.landmarks[pairs[k].landmark].plane, 1.0});
      const Pose3 refined = AlignPointsToPlanes(inlier_points, r.T_target_source, predicted, config_.prior_weight,
                                                config_.refine_iterations, config_.refine_robust_scale).T_target_source;
      return SeeThroughFraction(refined, cloud);
    };
    // Without a prediction to trust (relocalizing, or recovering: no frame tracked since the last
    // degraded one) a pose must not look through the map's surfaces, and one that only three
    // planes agree with (three always agree with the pose they give) needs the depth's verdict.
    // (or that most of the frame's planes agree with: a room's floor and two walls).
    const auto verified = [&](const PlaneRansacResult& r, const std::vector<Candidate>& pairs) {
      const double through = SeeThrough(r, pairs);
      if (through > config_.relocalize_max_see_through) return false;
      const int agreeing = static_cast<int>(r.inliers.size());
      return agreeing >= config_.min_agreeing_planes ||
             (through >= 0.0 && agreeing >= config_.min_agreeing_fraction * static_cast<double>(observed.size()));
    };
    // Searching without the prediction needs the depth to refute wrong poses (the camera's
    // intrinsics), and is for a camera without odometry: a robot's odometry predicts its pose
    // across any gap well enough for the search near it.
    const bool can_relocalize = config_.relocalize && camera_.has_value() && !odometry;
    if (can_relocalize && ransac.ok && unobserved_.trace() > 0.5 && !verified(ransac, candidates)) {
      ransac.ok = false;
      ransac.reason = "the best pose near the prediction looks through the mapped surfaces in view, or too few planes and no view of the map confirm it";
    }
    // 1b. No pose near the prediction, or one that most of the frame's planes do not agree with:
    // poses from plane correspondences found without it, as far from it as the camera can have
    // moved since the last pose, scored with the pairs near them.
    const double gap = std::max(0.0, stamp - history_.back().first);
    const bool weak = !ransac.ok || SupportFraction(ransac, candidates, observed) < config_.min_agreeing_fraction;
    if (weak && can_relocalize && observed.size() >= 3) {
      slack = config_.relocalize_max_speed * gap;
      slack_angle = config_.relocalize_max_turn_rate_deg * kDegToRad * gap;
      std::vector<Pose3> hypotheses = {predicted};
      if (ransac.inliers.size() >= 3) hypotheses.push_back(ransac.T_target_source);  // the nearby search's best
      std::vector<Candidate> wider = candidates;
      for (const RelocalizationHypothesis& h : Relocalize(observed)) {
        if (!reachable(h.T_target_source)) continue;
        hypotheses.push_back(h.T_target_source);
        for (Observation& o : observed) o.Place(h.T_target_source);
        for (const Candidate& c : Associate(observed, config_.relocalization.inlier_angle_deg, config_.relocalization.inlier_distance,
                                            gates.max_candidates, 0.0)) {
          const bool known = std::any_of(wider.begin(), wider.end(), [&](const Candidate& w) {
            return w.observation == c.observation && w.landmark == c.landmark;
          });
          if (!known) wider.push_back(c);
        }
      }
      // The best supported pose, unless the depth refutes it: then the next, a few times.
      const std::vector<PlaneCorrespondence> wider_pairs = Correspondences(wider, observed);
      for (int attempt = 0; attempt < config_.relocalize_attempts && hypotheses.size() > 1 + (ransac.inliers.size() >= 3); ++attempt) {
        PlaneRansacResult relocalized = EstimatePoseRansac(wider_pairs, ransac_config, hypotheses, plausibility);
        fixes_three_directions(&relocalized, wider);
        enough_evidence(&relocalized, wider);
        if (!relocalized.ok) break;
        if (!verified(relocalized, wider)) {
          refused_poses.push_back(relocalized.T_target_source);
          continue;
        }
        ransac = std::move(relocalized);
        candidates = wider;
        correspondences = wider_pairs;
        result.relocalized = true;
        break;
      }
      if (!result.relocalized) slack = slack_angle = 0.0;
    }
    if (ransac.ok) {
      // The closed form weighs offsets measured far from the origin; the inlier pairs' points
      // against their landmarks' planes refine it before the final association.
      std::vector<PointsOnPlane> groups;
      for (int k : ransac.inliers) {
        groups.push_back({observed[candidates[k].observation].moments, map_.landmarks[candidates[k].landmark].plane, 1.0});
      }
      T = ransac.T_target_source;
      const Pose3 aligned = AlignPointsToPlanes(groups, T, predicted, config_.prior_weight, config_.refine_iterations,
                                                config_.refine_robust_scale).T_target_source;
      // With odometry the sample's pose is near the truth already (the prediction, or a pose the
      // odometry's likelihood let win), and a refinement moving it more than refine_max_* is a
      // far plane's tilted normal speaking (the studio, seed 5: a locker face 4 m away, 3 deg
      // off, moved a standing robot 11 cm): refused, as in degraded frames.
      if (config_.refine == "points" && reachable(aligned) &&
          (!odometry || IsSmallCorrection(T.inverse() * aligned, config_.refine_max_translation,
                                          config_.refine_max_rotation_deg))) {
        T = aligned;
        result.refined = true;
      }
    } else {
      result.status = TrackStatus::kDegraded;
      result.reason = std::to_string(candidates.size()) + " candidate pairs for " + std::to_string(result.planes) +
                      " planes: " + ransac.reason + "; the directions the matched planes fix solved, the rest predicted";
      // The rotation, when two non-parallel planes fix it, from each plane's best candidate:
      // normals do not suffer from parallel look-alikes (a wall and a box face in front of it),
      // offsets do, so the translation waits for the tight association below.
      const auto rotation_plausibility = [&](const Eigen::Matrix3d& R) {
        Pose3 rotated = predicted;
        rotated.linear() = R;
        return plausibility(rotated);
      };
      std::vector<bool> agreeing;
      if (const auto R = SolveRotation(candidates, observed, predicted.linear(), rotation_plausibility, &agreeing)) {
        Pose3 rotated = predicted;
        rotated.linear() = *R;
        if (reachable(rotated)) {
          T = rotated;
          rotation_agrees = std::move(agreeing);
        }
      }
    }
    prior = T;
    // 2. At that pose (or the prediction), each plane's best landmark within the tight gates.
    for (Observation& o : observed) o.Place(T);
    for (const Candidate& c : Associate(observed, gates.max_angle_deg, gates.max_distance, 1, 0.0)) landmark_of[c.observation] = c.landmark;
    for (int l : landmark_of) result.matched += l >= 0;
    if (ransac.ok) result.inliers = static_cast<int>(ransac.inliers.size());
  }
  // Degraded: the tight matches refine what they fix (tracked frames were refined on RANSAC's
  // inlier pairs above, which agree with each other; a later, looser pairing only adds risk).
  // With a solved rotation only the planes that agreed with it: the one whose normal kept it
  // from a pose (a sliver whose fit took in a wall behind it) would move the position as well.
  std::vector<int> used;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (landmark_of[i] < 0 || result.status != TrackStatus::kDegraded) continue;
    if (!rotation_agrees.empty() && !rotation_agrees[i]) continue;
    used.push_back(static_cast<int>(i));
  }

  result.T_planes = T;
  std::vector<PointsOnPlane> silhouettes;  // degraded: box sides fixed by a face's silhouette
  if (!first && !used.empty() && config_.refine == "points") {
    // Every inlier of the used planes against its landmark's plane, from the closed-form pose (or,
    // degraded, from the prediction), the prediction as a weak prior for what no plane fixes.
    std::vector<PointsOnPlane> groups;
    for (int i : used) groups.push_back({observed[i].moments, map_.landmarks[landmark_of[i]].plane, 1.0});
    if (config_.use_silhouettes && result.status == TrackStatus::kDegraded) {
      silhouettes = SilhouetteGroups(model, cloud, observed, landmark_of, T);
      groups.insert(groups.end(), silhouettes.begin(), silhouettes.end());
    }
    const PointToPlaneResult aligned =
        AlignPointsToPlanes(groups, T, prior, config_.prior_weight, config_.refine_iterations, config_.refine_robust_scale);
    if (IsSmallCorrection(T.inverse() * aligned.T_target_source, config_.refine_max_translation, config_.refine_max_rotation_deg)) {
      // Degraded: along what no plane or silhouette fixes the solve is free, and a fixed normal's
      // slight tilt toward it would move the pose there by centimetres a frame (the studio's box
      // top, its far side's silhouette 1 deg off the grasp axis: 12 cm sideways in 0.6 s of
      // standing still); there the position stays the prediction's.
      const Pose3 before = T;
      T = aligned.T_target_source;
      if (result.status == TrackStatus::kDegraded) {
        Eigen::Matrix3d normals = Eigen::Matrix3d::Zero();
        for (const PointsOnPlane& g : groups) normals += g.target.normal * g.target.normal.transpose();
        T.translation() -= FreeDirections(normals, config_.ransac.min_normal_spread) * (T.translation() - before.translation());
      }
      result.refined = true;
      result.silhouettes = static_cast<int>(silhouettes.size());
    }
  } else if (result.status == TrackStatus::kTracked && !first && config_.refine == "icp") {
    // ICP on points rebuilt from the inliers of every extracted plane, against the landmarks'
    // points: it refines the closed-form pose with all the surface, not only the plane equations.
    pcl::PointCloud<pcl::PointNormal> source, target;
    for (const Observation& o : observed) {
      source += *PlanePoints(model.planes[o.plane], cloud, config_.point_stride);
    }
    for (size_t i = 0; i < observed.size(); ++i) {
      if (landmark_of[i] < 0) continue;
      const PlaneLandmark& l = map_.landmarks[landmark_of[i]];
      for (const Eigen::Vector3f& p : l.points) {
        pcl::PointNormal q;
        q.getVector3fMap() = p;
        q.getNormalVector3fMap() = l.plane.normal.cast<float>();
        target.push_back(q);
      }
    }
    if (!source.empty() && !target.empty()) {
      const IcpResult icp = RefineIcp(source, target, T, config_.icp);
      if (icp.converged &&
          IsSmallCorrection(T.inverse() * icp.T_target_source, config_.refine_max_translation, config_.refine_max_rotation_deg)) {
        T = icp.T_target_source;
        result.refined = true;
      }
    }
  }

  // Degraded: is the rotation still measured (two non-parallel matched planes, e.g. the floor and
  // a wall)? Then only a translation is predicted and the frame still maps; else the heading
  // drifts with the motion model, and after lost_after such frames the pose is lost.
  bool rotation_observed = result.status == TrackStatus::kTracked;
  Eigen::Matrix3d unobserved = Eigen::Matrix3d::Zero();  // projector onto what this frame's planes leave free
  if (!first && result.status == TrackStatus::kDegraded) {
    Eigen::Matrix3d normals = Eigen::Matrix3d::Zero();
    for (int i : used) normals += map_.landmarks[landmark_of[i]].plane.normal * map_.landmarks[landmark_of[i]].plane.normal.transpose();
    rotation_observed = NormalSingularValues(normals)[1] >= config_.ransac.min_normal_spread;
    if (!rotation_observed) result.reason += "; the rotation about the one plane normal is predicted too";
    // A silhouette fixes its side's offset (a position), not a rotation.
    for (int k = 0; k < result.silhouettes; ++k) {
      normals += silhouettes[k].target.normal * silhouettes[k].target.normal.transpose();
    }
    if (result.silhouettes > 0) {
      result.reason += "; " + std::to_string(result.silhouettes) + " box silhouettes";
    }
    unobserved = FreeDirections(normals, config_.ransac.min_normal_spread);
  }
  // With odometry, a heading that nothing in the map holds (every landmark horizontal: the floor
  // alone, for a robot that starts facing open floor in a large room) is the odometry's to give.
  // No mapped surface can disagree with it, so it is not lost over it, and the first wall seen is
  // mapped at it and holds it from then on. A landmark holds the heading when its normal leans
  // from the vertical by as much as a plane pair must spread (ransac.min_normal_spread).
  if (!rotation_observed && T_odometry_camera) {
    bool heading_held = false;
    for (const PlaneLandmark& l : map_.landmarks) {
      heading_held = heading_held || l.plane.normal.head<2>().norm() >= config_.ransac.min_normal_spread;
    }
    if (!heading_held) {
      rotation_observed = true;
      result.reason += "; the map holds no heading yet: the odometry's is taken";
    }
  }
  blind_run_ = rotation_observed || first ? 0 : blind_run_ + 1;
  if (rotation_observed || first) odometry_at_rotation_ = T_odometry_camera;
  if (const auto unmeasured = UnmeasuredMotion(T_odometry_camera)) {
    // With odometry the heading errs by the motion since the rotation was measured.
    const double turn = unmeasured->turn_deg, walked = unmeasured->walked;
    if (turn > config_.lost_after_turn_deg || walked > config_.lost_after_distance) {
      result.status = TrackStatus::kLost;
      char text[160];
      std::snprintf(text, sizeof(text), "rotation unobserved while the odometry turned %.0f deg and walked %.2f m: ",
                    turn, walked);
      result.reason = text + result.reason;
    }
  } else if (blind_run_ > config_.lost_after) {
    result.status = TrackStatus::kLost;
    result.reason = "rotation unobserved for " + std::to_string(blind_run_) + " frames: " + result.reason;
  }
  // The directions left unobserved since the last tracked frame: their union (a lost pose: all).
  if (result.status == TrackStatus::kTracked) {
    unobserved_.setZero();
  } else if (result.status == TrackStatus::kLost) {
    unobserved_.setIdentity();
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(unobserved_ + unobserved);
    unobserved_.setZero();
    for (int k = 0; k < 3; ++k) {
      if (eigen.eigenvalues()[k] > 0.5) unobserved_ += eigen.eigenvectors().col(k) * eigen.eigenvectors().col(k).transpose();
    }
  }
  result.T_world_camera = T;
  FrameObservations record;
  record.frame = frame;
  record.stamp = stamp;
  record.T_world_camera = T;
  record.degraded = result.status == TrackStatus::kDegraded;
  record.lost = result.status == TrackStatus::kLost;
  if (result.status == TrackStatus::kLost) {
    result.landmark_of_plane = LandmarkOfPlane(model, observed, landmark_of);
    observations_.push_back(std::move(record));
    return result;  // neither the motion model nor the map take a pose that may be anywhere
  }
  // The motion model remembers tracked and degraded poses: what their planes fix is measured.
  history_.emplace_back(stamp, T);
  odometry_at_last_ = T_odometry_camera;
  while (history_.size() > 2 && history_.back().first - history_[1].first >= config_.velocity_window) history_.pop_front();
  if (result.status == TrackStatus::kTracked) last_tracked_stamp_ = stamp;
  // Without odometry, a degraded frame is placed in part by the motion model's guess: when its
  // rotation is guessed, or its unobserved directions may have drifted more than
  // max_mapping_drift since the last tracked frame (max_speed per second), it neither adds to nor
  // updates the map, which would otherwise hold its surfaces as far off as the guess (a hand-held
  // camera turning 20 deg between two frames 0.17 s apart: every plane of the frame added again,
  // 20 deg turned; frames 2 s apart: planes added 14 cm off).
  const bool drifted = result.status == TrackStatus::kDegraded &&
                       config_.max_speed * (stamp - last_tracked_stamp_) > config_.max_mapping_drift;
  if (!first && (!rotation_observed || drifted) && !odometry) {
    result.reason += !rotation_observed ? "; not mapped (its rotation is the motion model's guess)"
                                        : "; not mapped (its position may have drifted beyond max_mapping_drift)";
    result.landmark_of_plane = LandmarkOfPlane(model, observed, std::vector<int>(observed.size(), -1));
    observations_.push_back(std::move(record));
    return result;
  }

  // The map: matched landmarks take the frame's inliers if they agree with them at the final
  // pose (a pairing that only the gates allowed must not bend a landmark); a landmark not yet
  // confirmed that the view disagrees with starts again from it (its first fit was the poor one:
  // a box top's first glancing strip, 3 deg tilted, would otherwise stay as it was and hold the
  // top's later views out of the map); unmatched planes become landmarks.
  for (size_t i = 0; i < observed.size(); ++i) {
    if (landmark_of[i] >= 0) {
      observed[i].Place(T);
      PlaneLandmark& l = map_.landmarks[landmark_of[i]];
      if (!Agrees(observed[i], l.plane)) {
        if (l.observations >= config_.confirm_views || l.last_frame == frame) {  // (or another part took it)
          landmark_of[i] = -1;
          continue;
        }
        PlaneLandmark fresh;
        fresh.id = l.id;
        fresh.first_frame = frame;
        l = std::move(fresh);
        voxels_[l.id].clear();
      }
    } else {
      // With odometry a degraded frame maps only planes no landmark could be (see the config).
      if (T_odometry_camera && result.status == TrackStatus::kDegraded && config_.odometry_degraded_adds_only_distinct) {
        observed[i].Place(T);
        if (!Associate({observed[i]}, gates.search_angle_deg, gates.search_distance, 1, 0.0).empty()) continue;
      }
      PlaneLandmark l;
      l.id = static_cast<int>(map_.landmarks.size());
      l.first_frame = frame;
      map_.landmarks.push_back(l);
      voxels_.emplace_back();
      landmark_of[i] = l.id;
      ++result.added;
    }
    PlaneLandmark& l = map_.landmarks[landmark_of[i]];
    const DetectedPlane& p = model.planes[observed[i].plane];
    for (size_t k = 0; k < p.inliers.size(); k += config_.point_stride) {
      const Eigen::Vector3d pw = T * cloud[p.inliers[k]].getVector3fMap().cast<double>();
      l.low = l.low.cwiseMin(pw);
      l.high = l.high.cwiseMax(pw);
      const Eigen::Vector3f pwf = pw.cast<float>();
      if (voxels_[l.id].insert(VoxelKey(pwf, config_.landmark_voxel)).second) l.points.push_back(pwf);
    }
    l.moments += TransformMoments(T, observed[i].moments);
    const PlaneFit fit = FitPlane(l.moments);
    const Plane observed_world = TransformPlane(T, p.plane);
    if (fit.ok) {
      l.plane = fit.plane.normal.dot(observed_world.normal) >= 0.0 ? fit.plane : fit.plane.Flipped();
    } else {
      l.plane = observed_world;
    }
    ++l.observations;
    l.last_frame = frame;
    // The back end sees the plane as the landmark takes it: fit with depth-noise weights.
    const PlaneFit own = FitPlane(observed[i].moments);
    Plane seen = own.ok ? own.plane : p.plane;
    if (seen.normal.dot(p.plane.normal) < 0.0) seen = seen.Flipped();
    record.planes.push_back({l.id, seen, own.ok ? own.covariance : p.covariance, own.ok ? own.centroid : p.centroid,
                             static_cast<int>(p.inliers.size())});
  }
  result.landmark_of_plane = LandmarkOfPlane(model, observed, landmark_of);
  if (model.floor >= 0 && result.landmark_of_plane[model.floor] >= 0) ++map_.landmarks[result.landmark_of_plane[model.floor]].floor_votes;
  MergeEdgesAndObjects(model, result.landmark_of_plane, T, &record);
  observations_.push_back(std::move(record));

  // Keyframes: the first frame, then one per keyframe_distance or keyframe_angle_deg of motion.
  if (map_.keyframes.empty() ||
      (map_.keyframes.back().T_world_camera.translation() - T.translation()).norm() > config_.keyframe_distance ||
      RotationAngle(map_.keyframes.back().T_world_camera.linear().transpose() * T.linear()) > config_.keyframe_angle_deg * kDegToRad) {
    map_.keyframes.push_back({frame, stamp, T});
  }
  return result;
}

int Tracker::SeenElsewhere(const MapObject& mo, const Eigen::Matrix3d& frame_axes, const Eigen::Vector3d& center, bool whole) const {
  if (mo.center_count < config_.object_moved_views) return -1;  // too few whole views to judge by
  if (std::abs(QuarterTurn(mo.axes, frame_axes)) > config_.object_moved_angle_deg * kDegToRad) return 1;
  if (!whole) return -1;  // a partial view's centre is not where the object's is
  return (center - mo.center).norm() > config_.object_moved_distance ? 1 : 0;
}

void Tracker::RestartMovedObject(const Eigen::Matrix3d& frame_axes, MapObject* mo) const {
  MapObject fresh;
  fresh.id = mo->id;
  fresh.label = mo->label;
  fresh.label_votes = mo->label_votes;
  fresh.observations = mo->observations;
  fresh.moves = mo->moves + 1;
  fresh.since_frame = mo->moved_from_frame;
  fresh.axes = frame_axes;
  *mo = std::move(fresh);
}

void Tracker::MergeEdgesAndObjects(const FrameModel& model, const std::vector<int>& landmark_of_plane,
                                   const Pose3& T_world_camera, FrameObservations* record) {
  // Edges: the merged edge is the longest one seen (paper, "Merging ... map representation").
  for (const PlaneEdge& e : model.edges) {
    int a = landmark_of_plane[e.plane_a], b = landmark_of_plane[e.plane_b];
    if (a < 0 || b < 0 || a == b) continue;
    if (a > b) std::swap(a, b);
    int k = map_.EdgeBetween(a, b);
    if (k < 0) {
      k = static_cast<int>(map_.edges.size());
      map_.edges.push_back(MapEdge{a, b});
    }
    MapEdge& m = map_.edges[k];
    ++m.observations;
    ++(e.convex ? m.convex_views : m.concave_views);
    m.complete = m.complete || e.Complete();
    if (e.length > m.length) {
      m.length = e.length;
      m.start = T_world_camera * e.start;
      m.end = T_world_camera * e.end;
    }
  }
  // Objects: a frame object is a map object seen again when it shares two faces with it, or, of
  // the same class or sharing a face, its centre lies within object_match_distance (a box seen
  // first from the side, its top unseen, votes "locker" until a view measures its height).
  const Eigen::Matrix3d R = T_world_camera.linear();
  for (const FrameObject& fo : model.objects) {
    // An object with a face seen only as a strip is left out, as the strip is. In the rendered
    // walks such objects started two spurious map objects (each seen once), and added to mapped
    // ones they moved the storeroom crate's centre from 3.4 to 4.4 mm and the office box's
    // width from -7.3 to -8.8 mm.
    if (std::any_of(fo.planes.begin(), fo.planes.end(), [&](int p) { return model.planes[p].strip; })) continue;
    std::vector<int> faces;
    for (int p : fo.planes) {
      if (landmark_of_plane[p] >= 0) faces.push_back(landmark_of_plane[p]);
    }
    // A face on a landmark the map knows to be room structure: a wall, of which the frame saw too
    // little to know it, taken for a face (in the generated rooms a low camera near a corner saw
    // two walls and the floor meet as a box's faces do, and the object stood in the planner's way
    // 1 m out from the corner). The map's extent of the surface decides as one view's does.
    if (std::any_of(faces.begin(), faces.end(), [&](int f) { return IsStructure(f); })) continue;
    const Eigen::Vector3d center = T_world_camera * fo.center;
    // The map object it is: the one sharing the most faces (two at least), else the one whose
    // cuboid it overlaps most (object_match_overlap of the smaller at least: a partial view's
    // cuboid lies inside the whole one's, a neighbour's only touches it), else one of its class
    // or sharing a face centred within object_match_distance.
    int match = -1, best_shared = 1;
    double best_overlap = config_.object_match_overlap;
    for (const MapObject& mo : map_.objects) {
      if (mo.structure) continue;
      int shared = 0;
      for (int f : faces) shared += std::count(mo.landmarks.begin(), mo.landmarks.end(), f) > 0;
      const double overlap = CuboidOverlap(mo.center, mo.axes, mo.dimensions, center, R * fo.axes, fo.dimensions);
      if (shared > best_shared || (best_shared < 2 && overlap > best_overlap)) {
        match = mo.id;
        best_shared = std::max(best_shared, shared);
        best_overlap = std::max(best_overlap, overlap);
      }
    }
    for (const MapObject& mo : map_.objects) {
      if (match >= 0) break;
      if (mo.structure) continue;
      const bool shares = std::any_of(faces.begin(), faces.end(), [&](int f) {
        return std::count(mo.landmarks.begin(), mo.landmarks.end(), f) > 0;
      });
      if ((mo.label == fo.label || shares) && (mo.center - center).norm() < config_.object_match_distance) match = mo.id;
    }
    if (match < 0) {
      MapObject mo;
      mo.id = static_cast<int>(map_.objects.size());
      mo.axes = R * fo.axes;
      map_.objects.push_back(mo);
      match = mo.id;
    }
    MapObject& mo = map_.objects[match];
    ++mo.observations;
    record->objects.push_back({mo.id, fo.axes, fo.dimensions, fo.dimension_complete, fo.center});
    if (mo.since_frame < 0) mo.since_frame = record->frame;
    const Eigen::Matrix3d frame_axes = R * fo.axes;
    const bool whole = std::all_of(fo.dimension_complete.begin(), fo.dimension_complete.end(), [](bool b) { return b; });
    const int disagrees = SeenElsewhere(mo, frame_axes, center, whole);
    if (disagrees == 0) mo.moved_views = 0;
    if (disagrees > 0) {
      if (mo.moved_views++ == 0) mo.moved_from_frame = record->frame;
      if (mo.moved_views < config_.object_moved_views) continue;  // not averaged in while it may be noise
      RestartMovedObject(frame_axes, &mo);
    }
    for (int f : faces) {
      if (std::find(mo.landmarks.begin(), mo.landmarks.end(), f) == mo.landmarks.end()) mo.landmarks.push_back(f);
    }
    std::sort(mo.landmarks.begin(), mo.landmarks.end());
    // Class: a view that measured the height (box or locker is decided by it) counts as
    // decided_vote_weight views that only bounded it from below.
    mo.label = Vote(&mo.label_votes, fo.label, fo.height_known ? config_.decided_vote_weight : 1);
    // Dimensions: each frame axis adds to the map axis most parallel to it. A complete edge gives
    // the mean of complete observations; without any, the longest seen bounds it from below.
    for (int j = 0; j < 3; ++j) {
      int k = 0;
      (mo.axes.transpose() * frame_axes.col(j)).cwiseAbs().maxCoeff(&k);
      if (fo.dimension_complete[j]) {
        ++mo.complete_count[k];
        mo.complete_sum[k] += fo.dimensions[j];
        mo.dimensions[k] = mo.complete_sum[k] / mo.complete_count[k];
        mo.dimension_complete[k] = true;
      } else {
        if (mo.complete_count[k] == 0) mo.dimensions[k] = std::max(mo.dimensions[k], fo.dimensions[j]);
      }
    }
    // Centre (eq. 7): the mean over views that saw every dimension whole, else over all views.
    if (whole) {
      ++mo.center_count;
      mo.center_sum += center;
    }
    ++mo.partial_center_count;
    mo.partial_center_sum += center;
    mo.center = mo.center_count > 0 ? Eigen::Vector3d(mo.center_sum / mo.center_count)
                                    : Eigen::Vector3d(mo.partial_center_sum / mo.partial_center_count);
    // Axes from the map's planes: z up as first seen, x the normal of the face that gave x first.
    if (mo.x_landmark < 0) {
      double best = 0.0;
      for (int p : fo.planes) {
        const double c = std::abs(fo.axes.col(0).dot(model.planes[p].plane.normal));
        if (landmark_of_plane[p] >= 0 && c > best) best = c, mo.x_landmark = landmark_of_plane[p];
      }
    }
    if (mo.x_landmark >= 0) {
      const Eigen::Vector3d z = mo.axes.col(2);
      Eigen::Vector3d x = map_.landmarks[mo.x_landmark].plane.normal;
      if (x.dot(mo.axes.col(0)) < 0.0) x = -x;
      x = (x - x.dot(z) * z).normalized();
      mo.axes.col(0) = x;
      mo.axes.col(1) = z.cross(x);
    } else if (mo.partial_center_count > 1) {
      // No face is a landmark (a moved object's faces can lie where its old faces were, which
      // they then do not update): the running mean of the views' turn about the vertical.
      const double turn = QuarterTurn(mo.axes, frame_axes);
      mo.axes = Eigen::AngleAxisd(turn / mo.partial_center_count, Eigen::Vector3d::UnitZ()) * mo.axes;
    }
    // Grasp axis: the normal of the landmark chosen as grasp side most often.
    if (fo.grasp_side >= 0 && landmark_of_plane[fo.grasp_side] >= 0) {
      mo.grasp_landmark = Vote(&mo.grasp_votes, landmark_of_plane[fo.grasp_side]);
    }
    if (mo.grasp_landmark >= 0) {
      mo.grasp_axis = map_.landmarks[mo.grasp_landmark].plane.normal;
      mo.has_grasp_axis = true;
    }
  }
  // An object mapped before one of its faces was known for a wall (seen from afar, a corner's two
  // walls each span less than structure_min_extent) is no object from the frame on that knows it.
  for (MapObject& mo : map_.objects) {
    mo.structure = mo.structure || std::any_of(mo.landmarks.begin(), mo.landmarks.end(), [&](int f) { return IsStructure(f); });
  }
}

}  // namespace planemap
