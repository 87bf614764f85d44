#pragma once
// Generated rooms for the approach (`planemap rooms`): seeded rooms of the kind a user's robot
// meets, never tuned for. A room is a scene file's contents (configs/scenes/*.yaml layout): walls,
// the box to fetch (`task: {object: box}`) and a few other things placed so that some hide the
// box or stand on the way. The robot starts at the world origin facing +x; every room is checked
// to have a pre-grasp pose the robot can reach from there on the true geometry.
#include <cstdint>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "planemap/core/config.h"
#include "planemap/nav/grasp.h"
#include "planemap/nav/planner.h"
#include "planemap/nav/pose2.h"

namespace planemap {

namespace sim {
struct Scene;
}

// The generator's ranges (configs/rooms/default.yaml). Each range is sampled uniformly.
struct RoomGeneratorConfig {
  double room_size_min = 4.0;        // each side of the rectangular room, from ... [m]
  double room_size_max = 8.0;        // ... to [m]
  double wall_height = 2.6;          // [m]
  double start_wall_margin = 0.6;    // the start (the origin) is at least this far from every wall [m]
  double box_narrow_min = 0.15;      // the box's narrower horizontal side, from ... [m]
  double box_narrow_max = 0.38;      // ... to: within the hands' span [m]
  double box_wide_extra_max = 0.25;  // its other horizontal side exceeds the narrower by up to this [m]
  double box_height_min = 0.10;      // [m]
  double box_height_max = 0.50;      // [m]
  double box_min_band = 0.02;        // graspable: some side the hands span has a standoff band
                                     // (nav/grasp.h) this wide, so the approach's own error of
                                     // about 1 cm either way still grasps it [m]
  double box_distance_min = 1.5;     // the box's centre from the start, from ... [m]
  double box_distance_max = 4.0;     // ... to [m]
  double near_wall_share = 0.3;      // rooms whose box stands by one wall [0-1] ...
  double corner_share = 0.2;         // ... in a corner (by two walls); the rest stand free [0-1]
  double wall_gap_min = 0.10;        // a box by a wall: its face to the wall, from ... [m]
  double wall_gap_max = 0.40;        // ... to [m]
  double wall_yaw_max_deg = 15.0;    // ... turned from the wall's direction by up to this [deg]
  double free_wall_margin = 0.6;     // a free-standing box's footprint keeps this far from walls [m]
  int others_min = 1;                // other things in the room, from ... [1]
  int others_max = 4;                // ... to [1]
  double hide_share = 0.5;           // rooms where one of them stands between the start and the box [0-1]
  double object_gap = 0.30;          // footprints of two things keep this far apart [m]
  double start_clearance = 0.45;     // other things' footprints keep this far from the start [m]
  double distinct_size = 0.08;       // another box differs from the target by this much in a dimension
                                     // (sorted horizontal extents or height): the task's size tells them apart [m]
  int max_attempts = 2000;           // placements tried before a room is given up [1]

  template <class V>
  void VisitFields(V&& v) {
    v("room_size_min", room_size_min, Check::kPositive);
    v("room_size_max", room_size_max, Check::kPositive);
    v("wall_height", wall_height, Check::kPositive);
    v("start_wall_margin", start_wall_margin, Check::kNonNegative);
    v("box_narrow_min", box_narrow_min, Check::kPositive);
    v("box_narrow_max", box_narrow_max, Check::kPositive);
    v("box_wide_extra_max", box_wide_extra_max, Check::kNonNegative);
    v("box_height_min", box_height_min, Check::kPositive);
    v("box_height_max", box_height_max, Check::kPositive);
    v("box_min_band", box_min_band, Check::kNonNegative);
    v("box_distance_min", box_distance_min, Check::kPositive);
    v("box_distance_max", box_distance_max, Check::kPositive);
    v("near_wall_share", near_wall_share, Check::kProbability);
    v("corner_share", corner_share, Check::kProbability);
    v("wall_gap_min", wall_gap_min, Check::kNonNegative);
    v("wall_gap_max", wall_gap_max, Check::kNonNegative);
    v("wall_yaw_max_deg", wall_yaw_max_deg, Check::kNonNegative);
    v("free_wall_margin", free_wall_margin, Check::kNonNegative);
    v("others_min", others_min, Check::kNonNegative);
    v("others_max", others_max, Check::kNonNegative);
    v("hide_share", hide_share, Check::kProbability);
    v("object_gap", object_gap, Check::kNonNegative);
    v("start_clearance", start_clearance, Check::kNonNegative);
    v("distinct_size", distinct_size, Check::kNonNegative);
    v("max_attempts", max_attempts, Check::kPositive);
  }
  std::string CrossCheck() const;
};

// Whether the robot can reach a pre-grasp pose of the scene's task object from `start` on the
// true geometry: an occupancy grid of the true footprints (every part below `body_height`, as the
// collision check holds them) inside the walls, the planner's A*, every side the hands can span.
struct RoomReach {
  bool ok = false;
  std::string reason;    // why not
  nav::Pose2 pre_grasp;  // the reachable one with the shortest path
  double path_length = 0.0;  // [m]
};
RoomReach CheckRoomReach(const sim::Scene& scene, const nav::Pose2& start, const nav::PlannerConfig& planner,
                         const nav::GraspConfig& grasp, double body_height);

struct GeneratedRoom {
  YAML::Node scene;        // a scene file's contents; sim::ParseScene reads it
  std::string summary;     // one line: size, the box and where it stands, the other things
  RoomReach reach;
  int attempts = 0;        // placements tried
};

// Room `index` of the generator's sequence for `seed`: the same arguments give the same room.
// Throws InputError when no room in max_attempts placements passes the reach check.
GeneratedRoom GenerateRoom(const RoomGeneratorConfig& config, std::uint64_t seed, int index,
                           const nav::PlannerConfig& planner, const nav::GraspConfig& grasp, double body_height);

}  // namespace planemap
