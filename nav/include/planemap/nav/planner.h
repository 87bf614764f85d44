#pragma once
// Path planning on the floor of a plane map (paper section 4.2: "the robot calculates a collision
// free path, and then follows it"): an occupancy grid from the map, A* with line-of-sight
// shortcuts, and the control points the controllers stop at.
//
// The target object. The pre-grasp pose stands nearer the object than robot_radius, so a plain
// inflated grid would block the goal. The grid keeps the target's footprint in a layer of its own:
// within approach_distance of the pre-grasp pose (the last straight leg, from an approach point
// set back along the grasp axis) the robot need only keep final_leg_radius from that footprint;
// everywhere else robot_radius, as from any obstacle. One rule, used by planning and by the
// runtime leg checks alike.
#include <optional>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/plane_map.h"
#include "planemap/nav/pose2.h"

namespace planemap::nav {

struct PlannerConfig {
  double resolution = 0.02;             // grid cell size [m]
  double robot_radius = 0.12;           // the base origin keeps this far from obstacles [m]
  double clearance_margin = 0.05;       // paths keep this much more where they can [m]
  double clearance_cost = 4.0;          // A* cost factor inside the margin, at full intrusion [-]
  double min_obstacle_height = 0.03;    // map points this high above the floor ... [m]
  double max_obstacle_height = 0.65;    // ... up to this are obstacles [m]
  double floor_margin = 0.10;           // unknown (blocked) border around the floor's extent [m]
  double control_point_spacing = 0.15;  // along the path [m]
  double approach_distance = 0.15;      // length of the last straight leg into the goal [m]
  double final_leg_radius = 0.08;       // on it, clearance kept from the target's footprint: the toes; below grasp.body_clearance [m]
  // Map points and objects this close to the target's footprint are the target's own surfaces
  // (a face the tracker holds twice, a part taken for an object), not obstacles.
  double target_margin = 0.05;          // [m]
  // Where the robot stands, its body: the map's obstacles within this of it are its own misplaced
  // surfaces (a phantom, a drifted landmark), not obstacles; it steps out from there (PlanPath) [m]
  double standing_radius = 0.08;

  template <class V>
  void VisitFields(V&& v) {
    v("resolution", resolution, Check::kPositive);
    v("robot_radius", robot_radius, Check::kNonNegative);
    v("clearance_margin", clearance_margin, Check::kNonNegative);
    v("clearance_cost", clearance_cost, Check::kNonNegative);
    v("min_obstacle_height", min_obstacle_height, Check::kAny);
    v("max_obstacle_height", max_obstacle_height, Check::kPositive);
    v("floor_margin", floor_margin, Check::kNonNegative);
    v("control_point_spacing", control_point_spacing, Check::kPositive);
    v("approach_distance", approach_distance, Check::kNonNegative);
    v("final_leg_radius", final_leg_radius, Check::kNonNegative);
    v("target_margin", target_margin, Check::kNonNegative);
    v("standing_radius", standing_radius, Check::kNonNegative);
  }
};

// The object the robot walks up to and where it will stand to grasp it.
struct GraspTarget {
  int object = -1;  // index into PlaneMap::objects; -1: no target
  Pose2 pre_grasp;  // world [m, rad]
};

// An oriented rectangle on the floor: an object's footprint.
struct Footprint {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();     // world [m]
  Eigen::Matrix2d axes = Eigen::Matrix2d::Identity();   // columns: unit side directions
  Eigen::Vector2d half_size = Eigen::Vector2d::Zero();  // along each column [m]
  // Distance from p to the rectangle, 0 inside [m].
  double Distance(const Eigen::Vector2d& p) const;
};
// The object's box (axes columns x, y; dimensions x, y) seen from above.
Footprint FootprintOf(const MapObject& object);

struct OccupancyGrid {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // centre of cell (0, 0), world [m]
  double resolution = 0.02;                          // [m]
  int width = 0, height = 0;                         // cells along world x and y
  // Per cell, a lower bound on the distance from any point of it to the nearest obstacle or
  // unknown cell, the target excluded [m].
  std::vector<float> clearance;
  GraspTarget target;
  Footprint target_footprint;  // exact, not rasterised: the last leg runs close to it
  PlannerConfig config;

  bool Empty() const { return width == 0 || height == 0; }
  // Clearance at p beyond what the robot needs there; negative: blocked (outside: -1) [m].
  double Slack(const Eigen::Vector2d& p) const;
  bool Free(const Eigen::Vector2d& p) const { return Slack(p) >= 0.0; }
  // Distance to the nearest obstacle of any kind, target included (lower bound) [m].
  double Clearance(const Eigen::Vector2d& p) const;
};

// Floor = free, out of the floor's extent = blocked; other landmarks' points in the height band
// and object footprints are obstacles. Empty when the map has no floor.
// `standing`: where the robot stands; the floor under and around it is free although the camera,
// pitched down ahead, has not seen it, and no obstacle lies within standing_radius of it.
OccupancyGrid BuildOccupancyGrid(const PlaneMap& map, const PlannerConfig& config, const GraspTarget& target = {},
                                 const std::optional<Eigen::Vector2d>& standing = std::nullopt);

struct PlanResult {
  bool ok = false;
  std::string reason;                 // why not, naming start, goal or path
  std::vector<Pose2> path;            // start, shortcut vertices (heading to the next), goal [m, rad]
  std::vector<Pose2> control_points;  // ControlPoints(path, ...): start first, goal last
  double length = 0.0;                // [m]
};

// A* (8-connected, extra cost in the clearance margin) to the approach point set back from the
// goal along its heading, shortcut by line of sight, then the straight leg into the goal; straight
// to the goal when that leg is impossible. A start inside the robot's clearance (not inside an
// obstacle) steps out first: a straight leg to the nearest free point within robot_radius +
// clearance_margin that comes no nearer any obstacle. Deterministic.
PlanResult PlanPath(const OccupancyGrid& grid, const Pose2& start, const Pose2& goal);

// Evenly spaced (at most `spacing` [m]) along the path, starting at its start, heading along it;
// the last one is `goal` with its heading.
std::vector<Pose2> ControlPoints(const std::vector<Pose2>& path, double spacing, const Pose2& goal);

// The least grid.Slack along the straight leg a -> b, sampled every half cell; -1 on an empty grid [m].
double SegmentSlack(const OccupancyGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b);

// Whether the robot's centre may move along the straight leg a -> b (grid.Free all along).
bool SegmentFree(const OccupancyGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b);

// Length of a polyline [m].
double PathLength(const std::vector<Pose2>& path);

}  // namespace planemap::nav
