#pragma once
// The walk to the pre-grasp pose in the paper's three scenarios (section 5, Table 1, Fig. 8):
// (1) open loop: relative motions between the control points, computed in advance;
// (2) path following: at each control point a P controller on the estimated pose's error to the
//     reference path; (3) as (2) for the first part, then object-relative approach: P steps on the
//     pose relative to the object's current estimate. Update() runs every camera frame; the robot
//     stops at each control point, stands still settle_time, then reads the estimate.
// Safety, in every scenario: each commanded leg is checked on the grid from the estimated pose
// (blocked: re-plan; scenario 1, which has no feedback, stops instead); no estimate for
// lost_timeout stops the robot until one comes back; standing, it turns on the spot
// (recovery_turn_deg, at most recovery_turns_max times) to bring mapped structure into view. In scenarios 2 and 3 an object estimate that
// stays object_moved_threshold away from where it was planned, or turned object_turned_threshold_deg
// from how, re-targets the pre-grasp pose.
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/plane_map.h"
#include "planemap/nav/grasp.h"
#include "planemap/nav/humanoid.h"
#include "planemap/nav/planner.h"
#include "planemap/nav/pose2.h"

namespace planemap::nav {

struct MissionState;  // mission.cpp

enum class Scenario { kOpenLoop = 1, kPathFeedback = 2, kObjectApproach = 3 };
enum class Phase { kPath, kApproach };

struct MissionConfig {
  double k_position = 0.8;      // path following: share of the along/cross-track error corrected [-]
  double k_heading = 0.8;       // ... of the heading error [-]
  double k_distance = 0.8;      // object approach: share of the offset to the pre-grasp pose walked [-]
  double k_angle = 0.8;         // ... of the angle between heading and grasp axis turned [-]
  int approach_steps_max = 12;  // object-approach steps before giving up
  double approach_position_tolerance = 0.01;    // the approach ends this close ... [m]
  double approach_heading_tolerance_deg = 2.0;  // ... and this well aligned [deg]
  int path_following_points = 8;          // scenario 3 follows the path to this control point (paper) ...
  double approach_switch_distance = 0.5;  // ... or until this much path is left [m]
  // ... and only this close to the pre-grasp pose (two max_step): the object-relative steps are the
  // last stretch, taken with the box in view; a longer way is the planned path's, which keeps the
  // camera on the way ahead [m].
  double approach_max_distance = 0.6;
  double settle_time = 0.5;               // standing still at a stop before reading the estimate [s]
  double lost_timeout = 0.5;              // without a pose estimate this long the robot stops [s]
  double give_up_timeout = 5.0;           // ... and this long the mission ends [s]
  // Lost and standing still settle_time, the robot turns on the spot this much to bring mapped
  // structure into view (the tracker finds its pose again from it) ... [deg]
  double recovery_turn_deg = 45.0;
  int recovery_turns_max = 8;  // ... at most this many times (a whole turn) before giving up
  double object_moved_threshold = 0.10;   // object estimate this far from the planned one ... [m]
  double object_turned_threshold_deg = 5.0;  // ... or turned this much about the vertical ... [deg]
  double object_moved_time = 0.3;         // ... this long: re-target and re-plan [s]
  double max_step = 0.30;                 // longest commanded walk in one feedback step [m]
  double max_turn_deg = 60.0;             // largest commanded turn in one feedback step [deg]
  int max_replans = 5;                    // more re-plans than this end the mission
  // Surfaces and objects first mapped after the plan this close to the target's footprint may be
  // the target itself, moved (tracking.object_match_distance): its estimate takes them, not the
  // obstacles of the grid rebuilt at each stop (Update with a map) [m].
  double moved_target_zone = 0.25;
  // Scenario 1 walks each leg blind: it stops rather than start one that, from the estimated pose,
  // keeps less slack than this to the nearest obstacle; the gait's error over one leg [m].
  double open_loop_margin = 0.02;

  template <class V>
  void VisitFields(V&& v) {
    v("k_position", k_position, Check::kNonNegative);
    v("k_heading", k_heading, Check::kNonNegative);
    v("k_distance", k_distance, Check::kPositive);
    v("k_angle", k_angle, Check::kPositive);
    v("approach_steps_max", approach_steps_max, Check::kNonNegative);
    v("approach_position_tolerance", approach_position_tolerance, Check::kPositive);
    v("approach_heading_tolerance_deg", approach_heading_tolerance_deg, Check::kPositive);
    v("path_following_points", path_following_points, Check::kNonNegative);
    v("approach_switch_distance", approach_switch_distance, Check::kNonNegative);
    v("approach_max_distance", approach_max_distance, Check::kPositive);
    v("settle_time", settle_time, Check::kNonNegative);
    v("lost_timeout", lost_timeout, Check::kPositive);
    v("give_up_timeout", give_up_timeout, Check::kPositive);
    v("recovery_turn_deg", recovery_turn_deg, Check::kPositive);
    v("recovery_turns_max", recovery_turns_max, Check::kNonNegative);
    v("object_moved_threshold", object_moved_threshold, Check::kPositive);
    v("object_turned_threshold_deg", object_turned_threshold_deg, Check::kPositive);
    v("object_moved_time", object_moved_time, Check::kNonNegative);
    v("max_step", max_step, Check::kPositive);
    v("max_turn_deg", max_turn_deg, Check::kPositive);
    v("max_replans", max_replans, Check::kNonNegative);
    v("moved_target_zone", moved_target_zone, Check::kNonNegative);
    v("open_loop_margin", open_loop_margin, Check::kNonNegative);
  }
};

struct ControlPointRecord {
  int index = 0;                  // control point of plan `plan` (0: its start); approach stops count on
  int plan = 0;                   // 0: the first plan, then one more per re-plan
  double time = 0.0;              // [s]
  Pose2 estimate;                 // the robot's estimated pose there [m, rad]
  Pose2 reference;                // the control point, or the object-derived pre-grasp pose when approaching
  double distance_to_path = 0.0;  // estimate to the reference path [m]
  Phase phase = Phase::kPath;
};

struct MissionStatus {
  enum class Outcome { kIdle, kRunning, kReached, kStopped } outcome = Outcome::kIdle;
  std::string reason;  // how it ended, or why it stopped
  bool Reached() const { return outcome == Outcome::kReached; }
};

class Mission {
 public:
  // `robot` must outlive the mission. Throws std::invalid_argument on an invalid config.
  Mission(Scenario scenario, const MissionConfig& config, const PlannerConfig& planner,
          const GraspConfig& grasp, Humanoid* robot);
  ~Mission();

  // Pre-grasp pose from the map's object, the grid, the reference path and its control points
  // (index 0 = start). Not ok (and the mission stays idle) for a bad index, an object the arms
  // cannot grasp, or no path.
  PlanResult Plan(const PlaneMap& map, int object_index, const Pose2& start_estimate);
  // A walk to a pose with no object (nav::Search's viewpoints): the same path following, no
  // approach phase, no object to watch; Update() gets a null object.
  PlanResult PlanTo(const PlaneMap& map, const Pose2& goal, const Pose2& start_estimate);
  // Every camera frame: time [s], the estimated base pose (nullopt: frame lost), the target
  // object's current estimate (world; may be null) and the current map (may be null). With a map,
  // every stop rebuilds the grid from it: an obstacle mapped since the plan (seen only on the way)
  // that the rest of the path crosses makes a re-plan; the next leg is checked against it.
  void Update(double time, const std::optional<Pose2>& estimate, const MapObject* object_estimate,
              const PlaneMap* map = nullptr);

  // Ends a running mission at once (the robot stops at its next footstep) with `reason`, as one
  // that may be chosen again (Blocked): the caller has learnt that its target is not the one
  // wanted (measured at another size on the way, say). Nothing when not running.
  void GiveUp(const std::string& reason);

  bool Done() const;
  // Stopped so that the caller may choose again from where the robot stands: a re-plan found no
  // path (an obstacle seen on the way blocks the goal or every way there), max_replans were used,
  // or GiveUp().
  bool Blocked() const;
  MissionStatus Status() const;
  const std::vector<ControlPointRecord>& Records() const;
  const std::vector<Pose2>& ReferencePath() const;
  const std::vector<Pose2>& ControlPoints() const;
  Pose2 PreGraspTarget() const;
  // The side of the object the robot grasps from: unit world xy axis out of that face.
  Eigen::Vector2d GraspSide() const;
  const OccupancyGrid& Grid() const;
  int Replans() const;

 private:
  std::unique_ptr<MissionState> state_;
};

// Distance from p to a polyline (its positions) [m]; infinity for an empty path.
double DistanceToPath(const std::vector<Pose2>& path, const Eigen::Vector2d& p);

}  // namespace planemap::nav
