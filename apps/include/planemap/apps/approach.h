#pragma once
// The live approach (paper, section 5): a simulated humanoid in a rendered scene walks to the
// pre-grasp pose in front of the box, closed loop. Every camera frame is rendered from the
// robot's true head pose, goes through the frontend, the tracker and the sliding window, and
// the mission (nav/) reads the smoothed base pose and the map's estimate of the box, and
// commands the next walk. Ground truth (the robot's true pose, the scene's box) only scores it.
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "planemap/core/plane_map.h"
#include "planemap/nav/mission.h"
#include "planemap/nav/planner.h"
#include "planemap/nav/search.h"
#include "planemap/nav/pose2.h"
#include "planemap/nav/simulated_humanoid.h"

namespace planemap {

struct ApproachOptions {
  std::string scene = "configs/scenes/default.yaml";
  std::string camera = "configs/cameras/xtion_nao.yaml";
  std::string config = "configs/default.yaml";
  std::string patterns = "configs/patterns.yaml";
  int scenario = 3;                           // 1 open loop, 2 path feedback, 3 object approach
  int seed = 1;                               // walking noise and sensor noise
  std::string target = "box";                 // the class of the object to approach ...
  std::vector<double> target_size;            // ... and its size: horizontal extents, height [m]
                                              // (empty: the scene's task object's, else any)
  std::vector<double> start{0.0, 0.0, 0.0};   // the robot's start: x y [m] heading [deg]
  double rate = 30.0;                         // camera frames per second [Hz]
  double look_time = 0.5;                     // standing at the start before planning [s] ...
  double look_timeout = 3.0;                  // ... and at most this long when no target is mapped,
                                              // then looks again from viewpoints (config search:) [s]
  double max_time = 240.0;                    // the run ends here whatever happens [s]
  double body_radius = 0.08;                  // the robot's true footprint, for collisions [m]
  double body_height = 0.58;                  // the robot's true height (Nao: 0.574 m), for collisions:
                                              // a part whose underside is above it (a table's top) is walked under [m]
  double move_object_at = -1.0;               // move the target in the scene at this time [s] (< 0: never)
  std::vector<double> move_object_by{0.10, 0.05, 10.0};  // by dx dy [m] dyaw [deg] in the world
  double drop_at = -1.0;                      // frames are lost from this time [s] (< 0: never) ...
  double drop_duration = 1.0;                 // ... for this long [s]
};

// One control point (stop) of a run.
struct ApproachStop {
  nav::ControlPointRecord record;  // as the mission saw it (estimate, reference, its distance)
  nav::Pose2 truth;                // where the robot really was
  double truth_to_path = 0.0;      // the true position's distance to the reference path [m]
};

// The gait's bias as the odometry calibration learnt it, and the simulated gait's true one.
struct GaitCalibration {
  double scale = 0.0, lateral = 0.0;  // forward scale error [-], sideways drift [m per m walked]
  double distance = 0.0;              // tracked walking it was learnt from [m]
  double scale_true = 0.0, lateral_true = 0.0;
};

// One camera frame of a run, for `planemap approach --trace`: what the tracker made of it, the
// smoothed base pose the controllers read, and where the robot really was.
struct ApproachFrame {
  double time = 0.0;           // [s]
  std::string phase;           // look (standing, no plan), search, path, approach
  std::string status;          // tracked, degraded, lost, dropped
  int planes = 0, matched = 0, inliers = 0, added = 0;  // TrackResult's counts
  bool refined = false;
  bool has_estimate = false;   // a smoothed base pose (not lost or dropped)
  nav::Pose2 tracked;          // the tracker's base pose (before the sliding window)
  nav::Pose2 estimate;         // the smoothed base pose
  nav::Pose2 truth;            // the true base pose
  std::string reason;          // why degraded or lost
};

struct ApproachRun {
  int scenario = 0, seed = 0;
  bool planned = false;
  nav::MissionStatus status;
  std::string target;                   // the scene object approached
  std::string intended;                 // the scene's task object (empty: none named); the run is
                                        // scored against it, and approaching another is a failure
  std::vector<nav::Viewpoint> viewpoints;  // where it looked again before the target was mapped
  std::vector<ApproachStop> stops;
  double average_error = 0.0;           // mean of truth_to_path over the stops [m]
  double position_error = 0.0;          // final true position to the true pre-grasp position [m]
  double heading_error = 0.0;           // final true heading to the true pre-grasp heading [rad]
  // The target's map estimate at the end against the true object: centre, and the extents along
  // the grasp axis (depth) and across it (width), estimated and true [m].
  double object_center_error = 0.0;
  double object_depth = 0.0, object_depth_true = 0.0;
  double object_width = 0.0, object_width_true = 0.0;
  bool grasp_ok = false;                // the grasp check at the final true pose on the true box
  std::string grasp_reason;
  GaitCalibration gait;
  bool collided = false;                // the true footprint touched an object
  std::string collision;                // which, and when
  double duration = 0.0;                // simulated time [s]
  int frames = 0, lost_frames = 0;
  // Per frame with a pose estimate: the smoothed base position's distance to the true one [m].
  std::vector<double> pose_errors;
  std::vector<double> perception_ms, estimation_ms, control_ms, render_ms;  // per processed frame
  // For plots: reference path, true and estimated base positions per frame, the true target.
  std::vector<nav::Pose2> reference, truth_path, estimate_path;
  nav::Pose2 pregrasp_true, pregrasp_planned;
  std::vector<nav::Footstep> footsteps;  // where the feet really landed
  std::vector<ApproachFrame> trace;      // every camera frame
  PlaneMap map;                          // the tracker's map at the end
  // Whether that map holds an object centred on the scene's task object's true footprint
  // (telling "never mapped" from "mapped and rejected" apart); none without a task object.
  std::optional<bool> task_object_mapped;

  // Approached another object than the scene's task names.
  bool WrongObject() const { return planned && !intended.empty() && target != intended; }
  // Ended at the pre-grasp pose of the object it was sent for.
  bool Reached() const { return status.Reached() && !WrongObject(); }
};

// What a run reads from files (scene, camera, settings, patterns), loaded and checked once: a
// table's runs share one snapshot, so editing a file while the table runs cannot change or stop it.
struct ApproachInputs;
// Throws InputError naming the file for unreadable or invalid inputs.
std::shared_ptr<const ApproachInputs> LoadApproachInputs(const ApproachOptions& options);

// One closed-loop run on inputs loaded from options' files (scenario and seed from options).
// Throws InputError for bad options.
ApproachRun RunApproachOnce(const ApproachOptions& options, const ApproachInputs& inputs);
// The same, loading the inputs first.
ApproachRun RunApproachOnce(const ApproachOptions& options);

namespace sim {
struct Scene;
}
// What the collision check holds the robot's true footprint (a disc of body_radius) against:
// the floor footprint of every part (cuboid) of every object whose underside is below
// `body_height` [m], by object name. A table's top above the robot is walked under, its legs not.
std::vector<std::pair<std::string, nav::Footprint>> CollisionFootprints(const sim::Scene& scene, double body_height);

}  // namespace planemap
