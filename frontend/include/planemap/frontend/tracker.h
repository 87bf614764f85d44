#pragma once
// Tracking and mapping (paper section 4.2): each frame's planes are associated with the map's
// plane landmarks after predicting the pose, the pose comes from >= 3 non-parallel plane
// correspondences in closed form inside RANSAC, then ICP on points rebuilt from the planes'
// inliers refines it. Frames are aligned to the map (the "updated first frame"), not to the
// previous frame; unmatched planes become landmarks, and the frame's edges and objects are merged
// into the map's.
#include <deque>
#include <string>
#include <unordered_set>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/frame_model.h"
#include "planemap/core/plane_map.h"
#include "planemap/frontend/organized_cloud.h"
#include "planemap/frontend/plane_registration.h"

namespace planemap {

struct AssociationConfig {
  double max_angle_deg = 8.0;    // predicted normal within this of the landmark's [deg]
  double max_distance = 0.08;    // predicted offset within this of the landmark's [m]
  double overlap_margin = 0.15;  // the predicted inliers' box within this of the landmark's [m]

  template <class V>
  void VisitFields(V&& v) {
    v("max_angle_deg", max_angle_deg, Check::kPositive);
    v("max_distance", max_distance, Check::kPositive);
    v("overlap_margin", overlap_margin, Check::kNonNegative);
  }
};

struct TrackingConfig {
  AssociationConfig association;
  PlaneRansacConfig ransac;
  IcpConfig icp;
  bool refine_icp = true;             // false: the closed-form RANSAC pose as it is
  int point_stride = 8;               // every n-th inlier is rebuilt as an ICP point
  double icp_max_translation = 0.05;  // an ICP correction beyond this is refused [m]
  double icp_max_rotation_deg = 3.0;  // ... or beyond this [deg]
  int min_landmark_inliers = 1000;    // smaller planes are neither matched nor added [px]
  double landmark_voxel = 0.05;       // a landmark keeps one point per voxel of this size [m]
  double velocity_window = 1.0;       // the motion model's velocity spans this much time [s]
  int lost_after = 30;                // degraded frames in a row before the pose is lost
  double keyframe_distance = 0.25;    // a keyframe every this much motion ... [m]
  double keyframe_angle_deg = 15.0;   // ... or turn [deg]
  double object_match_distance = 0.25;  // a frame object joins a map object this close [m]

  template <class V>
  void VisitFields(V&& v) {
    v("association", association);
    v("ransac", ransac);
    v("icp", icp);
    v("refine_icp", refine_icp);
    v("point_stride", point_stride, Check::kPositive);
    v("icp_max_translation", icp_max_translation, Check::kPositive);
    v("icp_max_rotation_deg", icp_max_rotation_deg, Check::kPositive);
    v("min_landmark_inliers", min_landmark_inliers, Check::kPositive);
    v("landmark_voxel", landmark_voxel, Check::kPositive);
    v("velocity_window", velocity_window, Check::kPositive);
    v("lost_after", lost_after, Check::kPositive);
    v("keyframe_distance", keyframe_distance, Check::kPositive);
    v("keyframe_angle_deg", keyframe_angle_deg, Check::kPositive);
    v("object_match_distance", object_match_distance, Check::kPositive);
  }
};

// tracked: pose from >= 3 non-parallel planes; degraded: too little structure (a corridor, one
// wall), the pose is the motion model's prediction; lost: degraded for lost_after frames.
enum class TrackStatus { kTracked, kDegraded, kLost };
const char* ToString(TrackStatus status);

struct TrackResult {
  Pose3 T_world_camera = Pose3::Identity();
  TrackStatus status = TrackStatus::kTracked;
  int planes = 0;       // frame planes large enough to track
  int matched = 0;      // associated with landmarks
  int inliers = 0;      // RANSAC inliers among them
  int added = 0;        // new landmarks
  bool icp = false;     // the ICP refinement was accepted
  std::string reason;   // why the frame is degraded or lost; empty when tracked
};

class Tracker {
 public:
  // The first frame's camera pose is T_world_first (the identity: the first frame is the world).
  explicit Tracker(const TrackingConfig& config, const Pose3& T_world_first = Pose3::Identity());

  // Tracks one frame (its model's planes index into `cloud`) and merges it into the map.
  TrackResult Track(const FrameModel& model, const Cloud& cloud, double stamp);

  const PlaneMap& map() const { return map_; }
  int frames() const { return frame_; }

 private:
  struct Observation;  // a frame plane in the world under a pose
  Pose3 Predict(double stamp) const;
  std::vector<int> Associate(const std::vector<Observation>& observed) const;
  void MergeEdgesAndObjects(const FrameModel& model, const std::vector<int>& landmark_of_plane,
                            const Pose3& T_world_camera);

  TrackingConfig config_;
  Pose3 T_world_first_;
  PlaneMap map_;
  std::vector<std::unordered_set<long long>> voxels_;  // per landmark: the voxels it holds
  std::deque<std::pair<double, Pose3>> history_;        // tracked poses within velocity_window
  int frame_ = 0;
  int degraded_run_ = 0;
};

}  // namespace planemap
