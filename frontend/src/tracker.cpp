#include "planemap/frontend/tracker.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace planemap {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

long long VoxelKey(const Eigen::Vector3f& p, double voxel) {
  const auto cell = [&](float x) { return static_cast<long long>(std::floor(x / voxel)) + (1LL << 20); };
  return (cell(p.x()) << 42) | (cell(p.y()) << 21) | cell(p.z());
}

// Relative motion as a twist (rotation vector, translation) and back.
Eigen::Matrix<double, 6, 1> Log(const Pose3& T) {
  const Eigen::AngleAxisd aa(T.linear());
  Eigen::Matrix<double, 6, 1> xi;
  xi << aa.angle() * aa.axis(), T.translation();
  return xi;
}

Pose3 Exp(const Eigen::Matrix<double, 6, 1>& xi) {
  Pose3 T = Pose3::Identity();
  const double angle = xi.head<3>().norm();
  if (angle > 1e-12) T.linear() = Eigen::AngleAxisd(angle, xi.head<3>() / angle).toRotationMatrix();
  T.translation() = xi.tail<3>();
  return T;
}

// What too few planes still fix: with two non-parallel normals the rotation (weighted Kabsch)
// and the translation along both normals; the rest of the translation (along their common
// direction) stays the prediction's. One plane or parallel planes: the prediction alone.
Pose3 SolveObservable(const std::vector<PlaneCorrespondence>& pairs, const Pose3& predicted, std::string* reason) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (const PlaneCorrespondence& c : pairs) H += c.weight * c.source.normal * c.target.normal.transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  if (pairs.size() < 2 || svd.singularValues()(1) < 0.05 * svd.singularValues()(0)) {
    *reason += "; pose predicted";
    return predicted;
  }
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  Pose3 T = Pose3::Identity();
  T.linear() = svd.matrixV() * D * svd.matrixU().transpose();
  // n_t . t = d_s - d_t for each pair, plus a weak pull to the predicted translation.
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const PlaneCorrespondence& c : pairs) {
    A += c.weight * c.target.normal * c.target.normal.transpose();
    b += c.weight * c.target.normal * (c.source.offset - c.target.offset);
  }
  const double lambda = 1e-6 * A.trace();
  T.translation() = (A + lambda * Eigen::Matrix3d::Identity()).ldlt().solve(b + lambda * predicted.translation());
  *reason += "; rotation and translation across the planes solved, along them predicted";
  return T;
}

// Counts one vote for `key` and returns the most voted key (the first on a tie).
template <typename Key>
Key Vote(std::vector<std::pair<Key, int>>* votes, const Key& key) {
  auto it = std::find_if(votes->begin(), votes->end(), [&](const auto& v) { return v.first == key; });
  if (it == votes->end()) {
    votes->emplace_back(key, 1);
  } else {
    ++it->second;
  }
  return std::max_element(votes->begin(), votes->end(), [](const auto& x, const auto& y) { return x.second < y.second; })->first;
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

// A frame plane as the tracker uses it: camera-frame plane and inlier box, and its world form
// under the current pose estimate.
struct Tracker::Observation {
  int plane = -1;                 // id in the frame model
  Plane camera;
  Eigen::Vector3d low_c, high_c;  // inlier box, camera frame [m]
  Plane world;
  Eigen::Vector3d low_w, high_w;  // that box's corners moved into the world, boxed again [m]
  int inliers = 0;

  void Place(const Pose3& T_world_camera) {
    world = TransformPlane(T_world_camera, camera);
    low_w = Eigen::Vector3d::Constant(1e30);
    high_w = -low_w;
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d c((k & 1) ? high_c.x() : low_c.x(), (k & 2) ? high_c.y() : low_c.y(), (k & 4) ? high_c.z() : low_c.z());
      const Eigen::Vector3d w = T_world_camera * c;
      low_w = low_w.cwiseMin(w);
      high_w = high_w.cwiseMax(w);
    }
  }
};

Tracker::Tracker(const TrackingConfig& config, const Pose3& T_world_first) : config_(config), T_world_first_(T_world_first) {
  ValidateConfig(config_, "tracking.");
}

Pose3 Tracker::Predict(double stamp) const {
  if (history_.empty()) return T_world_first_;
  const auto& [t1, T1] = history_.back();
  if (history_.size() < 2) return T1;
  // Constant velocity over the window: the mean motion per second since its oldest pose,
  // applied in the camera frame for the time since the last tracked pose.
  const auto& [t0, T0] = history_.front();
  if (t1 - t0 <= 1e-6) return T1;
  const Eigen::Matrix<double, 6, 1> xi = Log(T0.inverse() * T1) / (t1 - t0);
  return T1 * Exp(xi * (stamp - t1));
}

std::vector<int> Tracker::Associate(const std::vector<Observation>& observed) const {
  // Candidate pairs by normal angle and offset after prediction, with overlapping extents; then
  // each landmark and each plane used once, best score first.
  struct Candidate {
    double score;
    int observation, landmark;
  };
  std::vector<Candidate> candidates;
  const double max_angle = config_.association.max_angle_deg * kDegToRad;
  for (size_t i = 0; i < observed.size(); ++i) {
    for (const PlaneLandmark& l : map_.landmarks) {
      const double angle = NormalAngle(observed[i].world, l.plane);
      const double distance = std::abs(observed[i].world.offset - l.plane.offset);
      if (angle > max_angle || distance > config_.association.max_distance) continue;
      if (!l.Overlaps(observed[i].low_w, observed[i].high_w, config_.association.overlap_margin)) continue;
      candidates.push_back({angle / max_angle + distance / config_.association.max_distance, static_cast<int>(i), l.id});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.score < b.score || (a.score == b.score && (a.observation < b.observation || (a.observation == b.observation && a.landmark < b.landmark)));
  });
  std::vector<int> landmark_of(observed.size(), -1);
  std::vector<bool> used(map_.landmarks.size(), false);
  for (const Candidate& c : candidates) {
    if (landmark_of[c.observation] >= 0 || used[c.landmark]) continue;
    landmark_of[c.observation] = c.landmark;
    used[c.landmark] = true;
  }
  return landmark_of;
}

TrackResult Tracker::Track(const FrameModel& model, const Cloud& cloud, double stamp) {
  const int frame = frame_++;
  TrackResult result;
  // The frame's planes large enough to track, with their inlier boxes.
  std::vector<Observation> observed;
  for (const DetectedPlane& p : model.planes) {
    if (static_cast<int>(p.inliers.size()) < config_.min_landmark_inliers) continue;
    Observation o;
    o.plane = p.id;
    o.camera = p.plane;
    o.inliers = static_cast<int>(p.inliers.size());
    o.low_c = Eigen::Vector3d::Constant(1e30);
    o.high_c = -o.low_c;
    for (size_t k = 0; k < p.inliers.size(); k += 4) {
      const Eigen::Vector3d x = cloud[p.inliers[k]].getVector3fMap().cast<double>();
      o.low_c = o.low_c.cwiseMin(x);
      o.high_c = o.high_c.cwiseMax(x);
    }
    observed.push_back(o);
  }
  result.planes = static_cast<int>(observed.size());

  const Pose3 predicted = Predict(stamp);
  Pose3 T = predicted;
  std::vector<int> landmark_of(observed.size(), -1);
  const bool first = map_.landmarks.empty() && history_.empty();
  if (first) {
    T = T_world_first_;
  } else {
    for (Observation& o : observed) o.Place(predicted);
    landmark_of = Associate(observed);
    std::vector<PlaneCorrespondence> correspondences;
    std::vector<int> observation_of;
    for (size_t i = 0; i < observed.size(); ++i) {
      if (landmark_of[i] < 0) continue;
      // Weight by inlier count: big planes are fitted more precisely. (Inverse offset variances
      // span four orders of magnitude and starve the minimal samples' spread test.)
      correspondences.push_back({observed[i].camera, map_.landmarks[landmark_of[i]].plane,
                                 std::sqrt(static_cast<double>(observed[i].inliers))});
      observation_of.push_back(static_cast<int>(i));
    }
    result.matched = static_cast<int>(correspondences.size());
    // Weights relative to the best plane's, so the solver's spread test sees unit-scale rows.
    double max_weight = 0.0;
    for (const PlaneCorrespondence& c : correspondences) max_weight = std::max(max_weight, c.weight);
    for (PlaneCorrespondence& c : correspondences) c.weight /= max_weight;
    const PlaneRansacResult ransac = EstimatePoseRansac(correspondences, config_.ransac);
    if (ransac.ok) {
      T = ransac.T_target_source;
      result.inliers = static_cast<int>(ransac.inliers.size());
      // Correspondences RANSAC rejected are not matches: those planes may become landmarks.
      std::vector<bool> keep(correspondences.size(), false);
      for (int i : ransac.inliers) keep[i] = true;
      for (size_t k = 0; k < correspondences.size(); ++k) {
        if (!keep[k]) landmark_of[observation_of[k]] = -2;  // neither matched nor new
      }
    } else {
      result.status = TrackStatus::kDegraded;
      result.reason = std::to_string(result.matched) + " of " + std::to_string(result.planes) +
                      " planes matched: " + ransac.reason;
      T = SolveObservable(correspondences, predicted, &result.reason);
    }
  }

  if (result.status == TrackStatus::kTracked && !first && config_.refine_icp) {
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
      const Pose3 correction = T.inverse() * icp.T_target_source;
      if (icp.converged && correction.translation().norm() < config_.icp_max_translation &&
          RotationAngle(correction.linear()) < config_.icp_max_rotation_deg * kDegToRad) {
        T = icp.T_target_source;
        result.icp = true;
      }
    }
  }

  if (result.status == TrackStatus::kDegraded) {
    if (++degraded_run_ > config_.lost_after) {
      result.status = TrackStatus::kLost;
      result.reason = "degraded for " + std::to_string(degraded_run_) + " frames: " + result.reason;
    }
    result.T_world_camera = T;
    return result;  // the map is not touched by a pose it cannot trust
  }
  degraded_run_ = 0;
  result.T_world_camera = T;
  history_.emplace_back(stamp, T);
  while (history_.size() > 2 && history_.back().first - history_[1].first >= config_.velocity_window) history_.pop_front();

  // The map: matched landmarks take the frame's inliers; unmatched planes become landmarks.
  for (size_t i = 0; i < observed.size(); ++i) {
    if (landmark_of[i] == -2) continue;
    if (landmark_of[i] < 0) {
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
    PointMoments moments;
    for (size_t k = 0; k < p.inliers.size(); ++k) {
      const Eigen::Vector3f pc = cloud[p.inliers[k]].getVector3fMap();
      const Eigen::Vector3d pw = T * pc.cast<double>();
      moments.Add(pw, DepthNoiseWeight(pc.z()));
      l.low = l.low.cwiseMin(pw);
      l.high = l.high.cwiseMax(pw);
      const Eigen::Vector3f pwf = pw.cast<float>();
      if (k % config_.point_stride == 0 && voxels_[l.id].insert(VoxelKey(pwf, config_.landmark_voxel)).second) l.points.push_back(pwf);
    }
    l.moments += moments;
    const PlaneFit fit = FitPlane(l.moments);
    const Plane observed_world = TransformPlane(T, p.plane);
    if (fit.ok) {
      l.plane = fit.plane.normal.dot(observed_world.normal) >= 0.0 ? fit.plane : fit.plane.Flipped();
    } else {
      l.plane = observed_world;
    }
    ++l.observations;
    l.last_frame = frame;
  }
  std::vector<int> landmark_of_plane(model.planes.size(), -1);
  for (size_t i = 0; i < observed.size(); ++i) landmark_of_plane[observed[i].plane] = std::max(-1, landmark_of[i]);
  MergeEdgesAndObjects(model, landmark_of_plane, T);

  // Keyframes: the first frame, then one per keyframe_distance or keyframe_angle_deg of motion.
  if (map_.keyframes.empty() ||
      (map_.keyframes.back().T_world_camera.translation() - T.translation()).norm() > config_.keyframe_distance ||
      RotationAngle(map_.keyframes.back().T_world_camera.linear().transpose() * T.linear()) > config_.keyframe_angle_deg * kDegToRad) {
    map_.keyframes.push_back({frame, stamp, T});
  }
  return result;
}

void Tracker::MergeEdgesAndObjects(const FrameModel& model, const std::vector<int>& landmark_of_plane,
                                   const Pose3& T_world_camera) {
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
    m.complete = m.complete || e.Complete();
    if (e.length > m.length) {
      m.length = e.length;
      m.start = T_world_camera * e.start;
      m.end = T_world_camera * e.end;
    }
  }
  // Objects: a frame object is a map object seen again when it shares two faces with it, or, of
  // the same class, its centre lies within object_match_distance.
  const Eigen::Matrix3d R = T_world_camera.linear();
  for (const FrameObject& fo : model.objects) {
    std::vector<int> faces;
    for (int p : fo.planes) {
      if (landmark_of_plane[p] >= 0) faces.push_back(landmark_of_plane[p]);
    }
    const Eigen::Vector3d center = T_world_camera * fo.center;
    int match = -1;
    for (const MapObject& mo : map_.objects) {
      int shared = 0;
      for (int f : faces) shared += std::count(mo.landmarks.begin(), mo.landmarks.end(), f) > 0;
      if (shared >= 2 || (mo.label == fo.label && (mo.center - center).norm() < config_.object_match_distance)) {
        match = mo.id;
        break;
      }
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
    for (int f : faces) {
      if (std::find(mo.landmarks.begin(), mo.landmarks.end(), f) == mo.landmarks.end()) mo.landmarks.push_back(f);
    }
    std::sort(mo.landmarks.begin(), mo.landmarks.end());
    mo.label = Vote(&mo.label_votes, fo.label);
    // Dimensions: each frame axis adds to the map axis most parallel to it. A complete edge gives
    // the mean of complete observations; without any, the longest seen bounds it from below.
    const Eigen::Matrix3d frame_axes = R * fo.axes;
    bool all_complete = true;
    for (int j = 0; j < 3; ++j) {
      int k = 0;
      (mo.axes.transpose() * frame_axes.col(j)).cwiseAbs().maxCoeff(&k);
      if (fo.dimension_complete[j]) {
        ++mo.complete_count[k];
        mo.complete_sum[k] += fo.dimensions[j];
        mo.dimensions[k] = mo.complete_sum[k] / mo.complete_count[k];
        mo.dimension_complete[k] = true;
      } else {
        all_complete = false;
        if (mo.complete_count[k] == 0) mo.dimensions[k] = std::max(mo.dimensions[k], fo.dimensions[j]);
      }
    }
    // Centre (eq. 7): the mean over views that saw every dimension whole, else over all views.
    if (all_complete) {
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
}

}  // namespace planemap
