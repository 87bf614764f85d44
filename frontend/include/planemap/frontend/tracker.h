#pragma once
// Tracking and mapping (paper section 4.2): each frame's planes are associated with the map's
// plane landmarks after predicting the pose, the pose comes from >= 3 non-parallel plane
// correspondences in closed form inside RANSAC, then ICP on points rebuilt from the planes'
// inliers refines it. Frames are aligned to the map (the "updated first frame"), not to the
// previous frame; unmatched planes become landmarks, and the frame's edges and objects are merged
// into the map's.
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/frame_model.h"
#include "planemap/core/observations.h"
#include "planemap/core/plane_map.h"
#include "planemap/frontend/organized_cloud.h"
#include "planemap/frontend/plane_registration.h"
#include "planemap/frontend/plane_relocalization.h"

namespace planemap {

// Two passes: candidates for RANSAC within wide gates around the predicted pose (a humanoid turns
// on the spot faster than a constant-velocity model foresees), then, at RANSAC's pose, each plane's
// one landmark within tight gates for the refinement and the map.
struct AssociationConfig {
  double search_angle_deg = 20.0;  // candidates: predicted normal within this of the landmark's [deg]
  double search_distance = 0.30;   // ... and the predicted patch's centroid this close to its plane [m]
  int max_candidates = 3;          // ... the best this many per frame plane
  double max_angle_deg = 5.0;      // the match at the estimated pose: normals within this [deg]
  double max_distance = 0.05;      // ... and the patch's centroid this close to the landmark's plane [m]
  double overlap_margin = 0.15;    // both passes: the placed inliers' box within this of the landmark's [m]

  template <class V>
  void VisitFields(V&& v) {
    v("search_angle_deg", search_angle_deg, Check::kPositive);
    v("search_distance", search_distance, Check::kPositive);
    v("max_candidates", max_candidates, Check::kPositive);
    v("max_angle_deg", max_angle_deg, Check::kPositive);
    v("max_distance", max_distance, Check::kPositive);
    v("overlap_margin", overlap_margin, Check::kNonNegative);
  }
};

struct TrackingConfig {
  AssociationConfig association;
  // No closed-form refit: over many planes it weighs offsets measured far from the origin, and
  // the point-based refinement that follows does better.
  PlaneRansacConfig ransac = [] {
    PlaneRansacConfig c;
    c.refit = false;
    return c;
  }();
  IcpConfig icp;
  // After RANSAC: "points" aligns every inlier of the matched planes to its landmark plane
  // (point-to-plane, partners from the association); "icp" runs PCL's point-to-plane ICP with
  // nearest neighbours against the landmarks' voxel points; "none" keeps the closed-form pose.
  // A pose this far from the motion model's prediction is not considered: a walking robot at a
  // few frames per second cannot be there. Over the 1367 tracked frames of the tracking and
  // back-end tests' walks the prediction erred by 9.7 mm at the median, 25 mm at the 99th
  // percentile and 48 mm at most (frames after a recovery); at 0.15 m the storeroom walk's frame
  // 53 took a pose 12 cm off that a strip 3 deg tilted and a far wall strip's landmark agreed with
  // as well as the true pose's planes (docs/tracking.md). Rotations are less predictable (a
  // turn on the spot starts at once), so their bound is wider.
  double max_correction = 0.10;          // [m]
  double max_correction_deg = 20.0;      // [deg]
  // With odometry (a walking robot's dead reckoning) the prediction from the last pose errs by
  // about this much (tracked frames of the approach: 1.2 cm and 0.7 deg at the 99th percentile),
  // and a RANSAC hypothesis's support is weighed by 1 / (1 + m^2), m its correction over these
  // (along directions left unobserved, odometry_sigma plus their drift): in the corridor
  // (configs/scenes/corridor.yaml, seed 1) three planes of a standing robot otherwise agreed as
  // well with a pose 4 cm off, and it was taken.
  double odometry_sigma = 0.02;          // [m]
  double odometry_sigma_deg = 1.0;       // [deg]
  // ... and the heading's, while no planes measure the rotation (the floor alone), grows by
  // odometry_turn_heading_error per degree the odometry turned and odometry_walk_heading_error_deg
  // per metre it walked since they last did: a gait's turns come out a few per cent long or short
  // and each step drifts its heading a little (the simulated Nao: 0.3 deg per step, steps of at
  // most 10 deg or 4 cm). A heading 2 deg off after a turn over open floor was held against the
  // mapped wall that came back into view (generated room 48, docs/approach.md).
  double odometry_turn_heading_error = 0.05;     // [deg/deg]
  double odometry_walk_heading_error_deg = 7.5;  // [deg/m]
  std::string refine = "points";
  int refine_iterations = 10;            // Gauss-Newton iterations of "points"
  double refine_robust_scale = 0.01;     // Cauchy scale on a plane's mean point distance, "points" [m]
  double refine_max_translation = 0.05;  // a refinement moving the pose more is refused [m]
  double refine_max_rotation_deg = 3.0;  // ... or turning it more [deg]
  double prior_weight = 1e-6;            // pull toward the prediction, relative to the data (see AlignPointsToPlanes)
  int point_stride = 8;                  // every n-th inlier becomes a landmark / ICP point
  int min_landmark_inliers = 1000;       // smaller planes are neither matched nor added [px]
  // A landmark is confirmed once this many views agreed with it. Before, its pairs weigh in RANSAC
  // (support and closed form) in proportion to its views, and a view that disagrees with it
  // starts it again: in the garage (configs/scenes/garage.yaml, seed 9) a far wall strip and a
  // locker face mapped once, 4 deg off, outweighed the confirmed walls and put the pose 13 cm
  // off, and such a landmark never agreed with a later view, so it stayed as it was.
  int confirm_views = 3;                 // [frames]
  // Planes whose centroid is farther are neither matched nor added: a structured-light sensor's
  // depth comes in steps of z^2 / 350 m (5 cm at 4 m), and far walls break into tilted strips.
  double max_depth = 4.0;                // [m]
  // Nor are planes whose normal is less certain than max_normal_std_deg, RANSAC's inlier angle: a
  // far wall seen edge-on comes as a thin strip cut by the disparity steps, its normal off by
  // 5-20 deg and different in every frame, and it would be the one plane fixing a direction. The
  // fit's covariance takes the pixels as independent, but a structured-light sensor's errors are
  // not (its correlation window, the steps): it is scaled by correlated_pixels, the pixels that
  // err together. In the hall (configs/scenes/hall.yaml) such strips were off by 7-17 times the
  // independent-pixel standard deviation, hence 100 (10 x 10 px: factor 10 on the deviation).
  double max_normal_std_deg = 3.0;       // [deg]
  double correlated_pixels = 100.0;      // [px]
  // A matched plane refines the pose (tracked) and updates its landmark only when, placed at the
  // pose, its normal is within merge_max_angle_deg of the landmark's and its centroid within
  // merge_max_distance of the landmark's plane.
  double merge_max_angle_deg = 2.0;      // [deg]
  double merge_max_distance = 0.02;      // [m]
  // With odometry a degraded frame still maps (its unobserved directions follow the odometry), but
  // adds no landmark whose plane lies within the association's search gates of one mapped
  // (search_angle_deg, search_distance, overlapping): its pose, partly the odometry's, cannot tell
  // a surface seen again a little off from a new one, and a second copy of a wall holds every
  // later pose to the drift it was mapped with. (Without odometry degraded frames map only while
  // they may have drifted little, max_mapping_drift; there the rule left TUM fr1/rpy at stride 5,
  // where clutter puts a landmark near most new planes, unmapped: 5.5 -> 28.6 cm ATE.)
  bool odometry_degraded_adds_only_distinct = true;
  double landmark_voxel = 0.05;          // a landmark keeps one point per voxel of this size [m]
  double velocity_window = 1.0;          // the motion model's velocity spans this much time [s]
  int lost_after = 30;                   // frames in a row without a measured rotation before the pose is lost ...
  // ... or, with odometry (whose heading error grows with the motion, not with the frames: a
  // robot standing face to a shelf keeps its heading), once the odometry has turned or walked
  // this much since the rotation was last measured.
  double lost_after_turn_deg = 60.0;     // [deg]
  double lost_after_distance = 0.30;     // [m]
  double max_speed = 0.3;                // while degraded, unobserved directions may drift this fast, and with no
                                         // velocity known yet (the second frame) the robot may have moved this fast [m/s]
  int recovery_iterations = 2000;        // RANSAC samples while degraded (wider search)
  // Without odometry a degraded frame maps only while its unobserved directions may have drifted
  // (max_speed per second since the last tracked frame) at most this much: farther, its new
  // planes would be placed where no later view finds them again.
  double max_mapping_drift = 0.10;       // [m]
  // Without a prediction to trust: when the search around it finds no pose that fixes 3
  // directions, or one that less than min_agreeing_fraction of the frame's plane weight agrees
  // with (frames far apart in time, a fast turn, a track lost) the pose is searched for among
  // plane correspondences found without one (plane_relocalization.h), its hypotheses scored by
  // RANSAC with the others and checked against the depth (the tracker needs the camera's
  // intrinsics for that). Not with odometry, whose prediction holds across gaps. A pose so found may lie as far from the prediction as the camera
  // can move in the time since the last pose: a hand-held camera or a walking robot's head,
  // relocalize_max_speed and relocalize_max_turn_rate_deg beyond max_correction(_deg).
  bool relocalize = true;
  // A pose is taken when at least min_agreeing_planes planes agree with it, or planes carrying
  // min_agreeing_fraction of the frame's plane weight: three planes with normals spanning 3-D
  // agree with the translation they give, right or wrong (their normals check the rotation;
  // nothing checks their offsets).
  int min_agreeing_planes = 4;
  double min_agreeing_fraction = 0.5;
  RelocalizationConfig relocalization;
  double relocalize_max_speed = 1.5;           // [m/s]
  double relocalize_max_turn_rate_deg = 180.0; // [deg/s]
  // Among such poses agreed with alike (a room's walls a quarter turn apart), the nearer to the
  // prediction wins: support is weighed by 1 / (1 + relocalize_tie_break d^2), d the distance
  // over the bound above. Small: a tie-breaker, not a prior (at 1, a pose half the bound away lost
  // to a nearer one with less support: fr1/rpy 3.5 -> 9.1 cm ATE).
  double relocalize_tie_break = 0.01;          // [-]
  // ... and, when the tracker knows the camera, refused when the map's surfaces it places in view
  // lie in front of what the camera measures (it would be looking through them) at more than
  // relocalize_max_see_through of the checked surface points, a point counting as seen through
  // when the measured depth lies beyond it by more than relocalize_depth_tolerance plus
  // relocalize_depth_tolerance_per_m of its depth, there and relocalize_edge_px away on either
  // side (near a silhouette a pose a degree off moves a point over the edge);
  // relocalize_min_checked_points are needed for a verdict.
  double relocalize_max_see_through = 0.20;    // [fraction]
  double relocalize_depth_tolerance = 0.05;    // [m]
  double relocalize_depth_tolerance_per_m = 0.02;  // [m/m]
  int relocalize_edge_px = 6;                  // [px]
  int relocalize_attempts = 3;                 // refuted poses set aside before giving up
  int relocalize_min_checked_points = 50;
  double keyframe_distance = 0.25;       // a keyframe every this much motion ... [m]
  double keyframe_angle_deg = 15.0;      // ... or turn [deg]
  double object_match_distance = 0.25;   // a frame object joins a map object this close [m] ...
  double object_match_overlap = 0.5;     // ... or whose cuboid holds this share of the smaller one [0, 1]
  // A frame object with a face on a landmark longer than this (its inliers' box diagonal, as
  // graph.structure_min_extent measures one view's plane) is a piece of room structure: a wall
  // seen near by, too little of it in view for the frame to know it, taken for a face (a room's
  // corner, the nook between a wall and a locker). It is not mapped [m]
  double structure_min_extent = 2.0;
  // A view that measured an object's height counts as this many that only bounded it from below
  // (a box stared at from the side, its top unseen, collects "locker" votes: it must not outvote
  // the views that saw its top) [-]
  int decided_vote_weight = 1000;
  // A map object is seen moved when object_moved_views views in a row put it elsewhere: a whole
  // view's centre farther than object_moved_distance, or any view's axes turned more than
  // object_moved_angle_deg about the vertical. Its estimate then starts again from the last of
  // them (the back end takes its views from the first of them on); disagreeing views are not
  // averaged in meanwhile.
  double object_moved_distance = 0.05;   // [m]
  double object_moved_angle_deg = 8.0;   // [deg]
  int object_moved_views = 10;
  // Box silhouettes, in degraded frames only: where a matched face of a mapped cuboid ends against
  // background (silhouette.h), its last pixels lie on the cuboid's neighbouring face, placed by the
  // map object's centre, axes and whole dimensions; they fix what the planes leave free (at the
  // hall's pre-grasp pose the floor, the box top and one wall: the box top's far and side ends fix
  // the rest). Such pixels count for a side when within silhouette_max_distance of it at the
  // plane-fixed pose, at least silhouette_min_points of them, their distances to it spread by
  // at most silhouette_max_spread (a straight edge along it, not a ragged occlusion).
  bool use_silhouettes = true;
  double silhouette_min_gap = 0.03;      // the camera sees at least this much past the edge [m]
  int silhouette_max_missing = 3;        // pixels without depth skipped past the edge [px]
  double silhouette_max_distance = 0.05; // [m]
  int silhouette_min_points = 20;        // [px]
  double silhouette_max_spread = 0.01;   // standard deviation [m]

  template <class V>
  void VisitFields(V&& v) {
    v("association", association);
    v("ransac", ransac);
    v("icp", icp);
    v("max_correction", max_correction, Check::kPositive);
    v("max_correction_deg", max_correction_deg, Check::kPositive);
    v("odometry_sigma", odometry_sigma, Check::kPositive);
    v("odometry_sigma_deg", odometry_sigma_deg, Check::kPositive);
    v("odometry_turn_heading_error", odometry_turn_heading_error, Check::kNonNegative);
    v("odometry_walk_heading_error_deg", odometry_walk_heading_error_deg, Check::kNonNegative);
    v("refine", refine, OneOf{{"points", "icp", "none"}});
    v("refine_iterations", refine_iterations, Check::kPositive);
    v("refine_robust_scale", refine_robust_scale, Check::kNonNegative);
    v("refine_max_translation", refine_max_translation, Check::kPositive);
    v("refine_max_rotation_deg", refine_max_rotation_deg, Check::kPositive);
    v("prior_weight", prior_weight, Check::kPositive);
    v("point_stride", point_stride, Check::kPositive);
    v("min_landmark_inliers", min_landmark_inliers, Check::kPositive);
    v("confirm_views", confirm_views, Check::kPositive);
    v("max_depth", max_depth, Check::kPositive);
    v("max_normal_std_deg", max_normal_std_deg, Check::kPositive);
    v("correlated_pixels", correlated_pixels, Check::kPositive);
    v("merge_max_angle_deg", merge_max_angle_deg, Check::kPositive);
    v("merge_max_distance", merge_max_distance, Check::kPositive);
    v("odometry_degraded_adds_only_distinct", odometry_degraded_adds_only_distinct);
    v("landmark_voxel", landmark_voxel, Check::kPositive);
    v("velocity_window", velocity_window, Check::kPositive);
    v("lost_after", lost_after, Check::kPositive);
    v("lost_after_turn_deg", lost_after_turn_deg, Check::kPositive);
    v("lost_after_distance", lost_after_distance, Check::kPositive);
    v("max_speed", max_speed, Check::kNonNegative);
    v("recovery_iterations", recovery_iterations, Check::kPositive);
    v("max_mapping_drift", max_mapping_drift, Check::kPositive);
    v("relocalize", relocalize);
    v("min_agreeing_planes", min_agreeing_planes, Check::kPositive);
    v("min_agreeing_fraction", min_agreeing_fraction, Check::kNonNegative);
    v("relocalization", relocalization);
    v("relocalize_max_speed", relocalize_max_speed, Check::kNonNegative);
    v("relocalize_max_turn_rate_deg", relocalize_max_turn_rate_deg, Check::kNonNegative);
    v("relocalize_tie_break", relocalize_tie_break, Check::kNonNegative);
    v("relocalize_max_see_through", relocalize_max_see_through, Check::kNonNegative);
    v("relocalize_depth_tolerance", relocalize_depth_tolerance, Check::kPositive);
    v("relocalize_depth_tolerance_per_m", relocalize_depth_tolerance_per_m, Check::kNonNegative);
    v("relocalize_edge_px", relocalize_edge_px, Check::kNonNegative);
    v("relocalize_attempts", relocalize_attempts, Check::kPositive);
    v("relocalize_min_checked_points", relocalize_min_checked_points, Check::kPositive);
    v("keyframe_distance", keyframe_distance, Check::kPositive);
    v("keyframe_angle_deg", keyframe_angle_deg, Check::kPositive);
    v("object_match_distance", object_match_distance, Check::kPositive);
    v("object_match_overlap", object_match_overlap, Check::kPositive);
    v("structure_min_extent", structure_min_extent, Check::kPositive);
    v("decided_vote_weight", decided_vote_weight, Check::kPositive);
    v("object_moved_distance", object_moved_distance, Check::kPositive);
    v("object_moved_angle_deg", object_moved_angle_deg, Check::kPositive);
    v("object_moved_views", object_moved_views, Check::kPositive);
    v("use_silhouettes", use_silhouettes);
    v("silhouette_min_gap", silhouette_min_gap, Check::kPositive);
    v("silhouette_max_missing", silhouette_max_missing, Check::kNonNegative);
    v("silhouette_max_distance", silhouette_max_distance, Check::kPositive);
    v("silhouette_min_points", silhouette_min_points, Check::kPositive);
    v("silhouette_max_spread", silhouette_max_spread, Check::kPositive);
  }
};

// tracked: pose from >= 3 non-parallel planes; degraded: too little structure (a corridor, one
// wall), or the planes that agree with the best pose span fewer than 3 directions: what the
// matched planes fix is solved, the rest is the motion model's prediction, and the frame still
// maps; lost: the rotation went unmeasured (one plane or none) for lost_after frames (with
// odometry: while it turned lost_after_turn_deg or walked lost_after_distance): the pose is the
// prediction and neither the map nor the motion model take it.
enum class TrackStatus { kTracked, kDegraded, kLost };
const char* ToString(TrackStatus status);

struct TrackResult {
  Pose3 T_world_camera = Pose3::Identity();
  Pose3 T_predicted = Pose3::Identity();    // the motion model's pose
  Pose3 T_planes = Pose3::Identity();       // the plane-to-plane pose, before ICP
  std::vector<int> landmark_of_plane;       // per frame plane: the landmark it matched or became, else -1
  TrackStatus status = TrackStatus::kTracked;
  int planes = 0;       // frame planes large enough to track
  int matched = 0;      // associated with landmarks
  int inliers = 0;      // RANSAC inliers among them
  int added = 0;        // new landmarks
  bool refined = false; // the refinement (points or ICP) was accepted
  bool relocalized = false;  // the pose came from correspondences searched for without the prediction
  int silhouettes = 0;  // degraded: box sides whose silhouette pixels took part in the refinement
  std::string reason;   // why the frame is degraded or lost; empty when tracked
};

class Tracker {
 public:
  // The first frame's camera pose is T_world_first (the identity: the first frame is the world).
  explicit Tracker(const TrackingConfig& config, const Pose3& T_world_first = Pose3::Identity());
  // With the camera's intrinsics a pose found without the prediction is also checked against the
  // frame's depth (the map's surfaces must not lie in front of what the camera measures).
  Tracker(const TrackingConfig& config, const Pose3& T_world_first, const CameraIntrinsics& camera);

  // Tracks one frame (its model's planes index into `cloud`) and merges it into the map.
  // `T_odometry_camera`, when the platform has odometry (a walking robot's dead reckoning carried
  // to its camera), is the camera pose in the odometry's own drifting frame at `stamp`: the
  // prediction is then the last accepted pose moved by the odometry's motion since it, instead
  // of constant velocity. Where the matched planes fix the pose it is measured; where they do
  // not (one wall and the floor, say) it follows the odometry, which knows when the robot stands.
  TrackResult Track(const FrameModel& model, const Cloud& cloud, double stamp,
                    const std::optional<Pose3>& T_odometry_camera = std::nullopt);

  const PlaneMap& map() const { return map_; }
  int frames() const { return frame_; }
  // Per frame tracked so far (lost ones too): its pose and what it observed, for the back end.
  const std::vector<FrameObservations>& observations() const { return observations_; }

 private:
  struct Observation;  // a frame plane in the world under a pose
  Pose3 Predict(double stamp, const std::optional<Pose3>& T_odometry_camera) const;
  struct Motion {
    double turn_deg, walked;  // [deg], [m]
  };
  // The odometry's net motion since the rotation was last measured; none without odometry.
  std::optional<Motion> UnmeasuredMotion(const std::optional<Pose3>& T_odometry_camera) const;
  // Whether the map knows a landmark for room structure: longer than structure_min_extent.
  bool IsStructure(int landmark) const;
  struct Candidate {
    int observation, landmark;
    double score;  // angle / gate + distance / gate: lower is better
  };
  // Landmarks within the gates of each placed observation, best first, at most `per_plane` each.
  // Per frame-model plane: the landmark its observation matched or became, else -1.
  static std::vector<int> LandmarkOfPlane(const FrameModel& model, const std::vector<Observation>& observed,
                                          const std::vector<int>& landmark_of);
  // RANSAC's pairs for candidates, weighted (Observation::Weight, Confirmed), relative to the heaviest.
  std::vector<PlaneCorrespondence> Correspondences(const std::vector<Candidate>& candidates,
                                                   const std::vector<Observation>& observed) const;
  // The share of the frame's plane weight (Observation::Weight) whose planes agree with RANSAC's pose.
  static double SupportFraction(const PlaneRansacResult& ransac, const std::vector<Candidate>& candidates,
                                const std::vector<Observation>& observed);
  // The share of the map's surface points placed in view by T_world_camera that the camera sees
  // through (see relocalize_max_see_through); negative when too few are in view to tell, or the
  // camera is unknown.
  double SeeThroughFraction(const Pose3& T_world_camera, const Cloud& cloud) const;
  // Pose hypotheses from the frame's planes and the map's without the prediction.
  std::vector<RelocalizationHypothesis> Relocalize(const std::vector<Observation>& observed) const;
  // 1 for a landmark seen in confirm_views frames or more, else the fraction of them it was seen
  // in: its weight in RANSAC.
  double Confirmed(const PlaneLandmark& l) const;
  // Whether a placed observation lies on `landmark` within merge_max_angle_deg / merge_max_distance.
  bool Agrees(const Observation& o, const Plane& landmark) const;
  // The world-from-camera rotation from the normals of each plane's best candidate that agree
  // with the best-supported hypothesis (the predicted rotation, or one from two non-parallel
  // planes; support: the agreeing planes' weight times `plausibility`), when they span two
  // directions or more. `agreeing`: per observation, whether its normal agreed.
  std::optional<Eigen::Matrix3d> SolveRotation(const std::vector<Candidate>& candidates,
                                               const std::vector<Observation>& observed, const Eigen::Matrix3d& predicted,
                                               const std::function<double(const Eigen::Matrix3d&)>& plausibility,
                                               std::vector<bool>* agreeing) const;
  // The distance gate widens by `drift` times the landmark normal's part along unobserved_.
  std::vector<Candidate> Associate(const std::vector<Observation>& observed, double max_angle_deg,
                                   double max_distance, int per_plane, double drift) const;
  // Degraded frames: per cuboid side next to a matched face, that face's silhouette pixels
  // (camera frame) against the side's plane (world), at the pose T the planes fixed.
  std::vector<PointsOnPlane> SilhouetteGroups(const FrameModel& model, const Cloud& cloud,
                                              const std::vector<Observation>& observed,
                                              const std::vector<int>& landmark_of, const Pose3& T) const;
  // Merges the frame's edges and objects into the map; records the object matches in `record`.
  void MergeEdgesAndObjects(const FrameModel& model, const std::vector<int>& landmark_of_plane,
                            const Pose3& T_world_camera, FrameObservations* record);
  // Whether a view (world axes and centre, all dimensions whole or not) puts an established map
  // object elsewhere: 1 it does, 0 it agrees, -1 it cannot tell.
  int SeenElsewhere(const MapObject& mo, const Eigen::Matrix3d& frame_axes, const Eigen::Vector3d& center, bool whole) const;
  // A moved object keeps its id, class and count of views; its estimate starts again.
  void RestartMovedObject(const Eigen::Matrix3d& frame_axes, MapObject* mo) const;

  TrackingConfig config_;
  Pose3 T_world_first_;
  std::optional<CameraIntrinsics> camera_;
  PlaneMap map_;
  std::vector<FrameObservations> observations_;
  std::vector<std::unordered_set<long long>> voxels_;  // per landmark: the voxels it holds
  std::deque<std::pair<double, Pose3>> history_;        // tracked and degraded poses within velocity_window
  std::optional<Pose3> odometry_at_last_;               // the odometry's camera pose at history_.back()
  int frame_ = 0;
  int blind_run_ = 0;                    // frames in a row whose rotation was not measured
  std::optional<Pose3> odometry_at_rotation_;  // the odometry's camera pose when it last was
  double last_tracked_stamp_ = 0.0;
  // Projector onto the world translation directions no plane has fixed since the last tracked
  // frame (along a single wall: the wall's direction); zero while tracked.
  Eigen::Matrix3d unobserved_ = Eigen::Matrix3d::Zero();
};

}  // namespace planemap
