#pragma once
// A walking robot's head camera trajectory: a polyline walked at constant speed, with the head
// swaying sideways, bobbing and rolling at the step frequency, as a small humanoid's does.
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/tum_format.h"

namespace planemap::sim {

struct WalkConfig {
  std::vector<double> waypoints{0.0, 0.0, 1.5, 0.0};  // x0 y0 x1 y1 ... on the floor [m]
  double speed = 0.10;             // walking speed [m/s]
  double turn_rate_deg = 30.0;     // turning on the spot at corners [deg/s]
  double rate = 30.0;              // camera frame rate [Hz]
  double start_stamp = 0.0;        // stamp of the first frame [s]
  double hold = 0.5;               // standing still at start and end [s]
  double camera_height = 0.52;     // camera above the floor [m]
  double camera_pitch_deg = 20.0;  // camera tilted down [deg]
  double sway_lateral = 0.012;     // head sway amplitude, sideways [m]
  double sway_vertical = 0.004;    // head bob amplitude [m]
  double sway_roll_deg = 1.0;      // head roll amplitude [deg]
  double sway_yaw_deg = 1.0;       // head yaw amplitude [deg]
  double step_frequency = 2.0;     // steps per second [Hz]; sway repeats every two steps

  template <class V>
  void VisitFields(V&& v) {
    v("waypoints", waypoints);
    v("speed", speed, Check::kPositive);
    v("turn_rate_deg", turn_rate_deg, Check::kPositive);
    v("rate", rate, Check::kPositive);
    v("start_stamp", start_stamp, Check::kNonNegative);
    v("hold", hold, Check::kNonNegative);
    v("camera_height", camera_height, Check::kPositive);
    v("camera_pitch_deg", camera_pitch_deg);
    v("sway_lateral", sway_lateral, Check::kNonNegative);
    v("sway_vertical", sway_vertical, Check::kNonNegative);
    v("sway_roll_deg", sway_roll_deg, Check::kNonNegative);
    v("sway_yaw_deg", sway_yaw_deg, Check::kNonNegative);
    v("step_frequency", step_frequency, Check::kPositive);
  }
};

// Camera poses T_world_camera (optical frame) at `rate` along the walk. Throws
// std::invalid_argument for fewer than two waypoints or an odd number of coordinates.
Trajectory GenerateWalk(const WalkConfig& config);

// A trajectory from a file: a walk description (.yaml) or a TUM trajectory (anything else).
Trajectory LoadTrajectory(const std::string& file);

}  // namespace planemap::sim
