#include "planemap/nav/mission.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace planemap::nav {

using Outcome = MissionStatus::Outcome;

struct MissionState {
  Scenario scenario = Scenario::kOpenLoop;
  MissionConfig config;
  PlannerConfig planner;
  GraspConfig grasp;
  Humanoid* robot = nullptr;

  PlaneMap map;  // a copy: re-targeting rebuilds the grid with the object moved
  size_t planned_landmarks = 0, planned_objects = 0;  // the map's sizes at the last plan
  int object_index = -1;
  MapObject object;                                          // the target's latest estimate (world)
  Eigen::Vector2d planned_center = Eigen::Vector2d::Zero();  // where the target was at the last plan [m]
  Eigen::Matrix3d planned_axes = Eigen::Matrix3d::Identity();  // and how it was turned
  // g chosen at the last plan; the approach keeps this face.
  Eigen::Vector2d grasp_axis = Eigen::Vector2d::UnitX();
  Pose2 pre_grasp;
  OccupancyGrid grid;
  std::vector<Pose2> path, control_points;
  std::vector<Pose2> legs;  // scenario 1: motions between control points, computed in advance
  int plan = 0, replans = 0;
  int target = 0;                // the control point walked to (0: at the start)
  bool command_complete = true;  // the robot, once stopped, ended the command meant for `target`
  Phase phase = Phase::kPath;
  int approach_steps = 0;
  int recovery_turns = 0;  // turns on the spot since the estimate was lost
  std::optional<double> first_time, last_estimate_time, still_since, moved_since, replanned_at;  // [s]
  bool lost = false, retarget = false;
  bool blocked = false;  // stopped for want of a way on from where the robot stands
  MissionStatus status;
  std::vector<ControlPointRecord> records;
  std::string goal_name = "the pre-grasp pose";  // PlanTo: "the viewpoint"
};

namespace {

using State = MissionState;

constexpr double kDeg = M_PI / 180.0;

std::string Format(const char* format, double a, double b = 0.0) {
  char text[200];
  std::snprintf(text, sizeof(text), format, a, b);
  return text;
}

void Finish(State& s, Outcome outcome, std::string reason) {
  if (outcome == Outcome::kStopped) s.robot->Stop();
  s.status = {outcome, std::move(reason)};
}

// The pose on the leg a -> b nearest to p, its heading interpolated: the reference for the
// path-following errors (an overshoot along the path counts as progress, not as error).
Pose2 NearestOnLeg(const Pose2& a, const Pose2& b, const Pose2& p) {
  const Eigen::Vector2d d = b.Position() - a.Position();
  const double t = d.squaredNorm() < 1e-12
                       ? 0.0
                       : std::clamp((p.Position() - a.Position()).dot(d) / d.squaredNorm(), 0.0, 1.0);
  const Eigen::Vector2d q = a.Position() + t * d;
  return {q.x(), q.y(), WrapAngle(a.theta + t * WrapAngle(b.theta - a.theta))};
}

// Limits a feedback command to max_step and max_turn_deg; whether it had to.
bool Clamp(const MissionConfig& config, Pose2* command) {
  bool clamped = false;
  const double length = std::hypot(command->x, command->y);
  if (length > config.max_step) {
    command->x *= config.max_step / length;
    command->y *= config.max_step / length;
    clamped = true;
  }
  const double max_turn = config.max_turn_deg * kDeg;
  if (std::abs(command->theta) > max_turn) {
    command->theta = std::copysign(max_turn, command->theta);
    clamped = true;
  }
  return clamped;
}

// The pre-grasp pose from the object's current estimate, on the face chosen at planning: an
// estimate that switched grasp faces mid-approach would send the robot round the object.
// The grid's target follows the estimate too: the approach legs are checked against the object
// as now seen (its footprint is exact in the grid, so moving it costs nothing).
// The target as the hands meet it: placed by its faces' mapped planes (AnchoredToMappedFaces).
MapObject Grasped(const State& s) { return AnchoredToMappedFaces(s.object, s.map.landmarks, s.grasp); }

Pose2 TrackObject(State& s) {
  const Pose2 goal = PreGraspPose(Grasped(s), s.grasp, s.grasp_axis);
  s.grid.target_footprint = FootprintOf(s.object);
  s.grid.target.pre_grasp = goal;
  return goal;
}

void Record(State& s, double time, const Pose2& estimate, int index, const Pose2& reference, Phase phase) {
  s.records.push_back(
      {index, s.plan, time, estimate, reference, DistanceToPath(s.path, estimate.Position()), phase});
}

// Grid, path and control points to the current pre-grasp pose from `from`.
PlanResult MakePlan(State& s, const Pose2& from) {
  s.planned_landmarks = s.map.landmarks.size();
  s.planned_objects = s.map.objects.size();
  s.grid = BuildOccupancyGrid(s.map, s.planner, {s.object_index, s.pre_grasp}, from.Position());
  PlanResult result = PlanPath(s.grid, from, s.pre_grasp);
  if (!result.ok) return result;
  s.path = result.path;
  s.control_points = result.control_points;
  s.target = 0;
  s.command_complete = true;
  s.phase = Phase::kPath;
  s.approach_steps = 0;
  return result;
}

// The pre-grasp pose, grasp face and grid follow the object's latest estimate. The grasp side is
// `side`'s nearest when given (the side a plan reached), else chosen anew (ChooseGraspSide).
void Retarget(State& s, const Pose2& from, const std::optional<Eigen::Vector2d>& side = std::nullopt) {
  MapObject& planned = s.map.objects[s.object_index];
  const std::vector<int> faces = planned.landmarks;  // the grid leaves the target's faces out
  planned = s.object;
  planned.landmarks = faces;
  const Eigen::Vector2d toward_robot = from.Position() - s.object.center.head<2>();
  s.grasp_axis = side ? GraspFaces(s.object, *side).axis : ChooseGraspSide(s.object, s.grasp, toward_robot);
  s.pre_grasp = PreGraspPose(Grasped(s), s.grasp, s.grasp_axis);
  s.planned_center = s.object.center.head<2>();
  s.planned_axes = s.object.axes;
  s.moved_since.reset();
}

bool Replan(State& s, const Pose2& from, bool retarget) {
  if (s.replans >= s.config.max_replans) {
    Finish(s, Outcome::kStopped, "gave up after " + std::to_string(s.replans) + " re-plans (max_replans)");
    s.blocked = true;
    return false;
  }
  ++s.replans;
  ++s.plan;
  if (retarget) Retarget(s, from, s.grasp_axis);
  const PlanResult result = MakePlan(s, from);
  if (!result.ok) {
    Finish(s, Outcome::kStopped, "re-planning from the estimated pose failed: " + result.reason);
    s.blocked = true;
  }
  return result.ok;
}

void PathStep(State& s, double time, const Pose2& estimate);

// Walks `command` (base frame) if its straight leg from the estimate is free (or, from inside the
// clearance, comes no nearer an obstacle); else re-plans
// (scenarios 2, 3) or stops (scenario 1: the open loop has no plan to change).
// Scenario 1 also stops when the leg would keep less than open_loop_margin: it cannot correct
// the gait's error on the way.
bool Issue(State& s, double time, const Pose2& estimate, const Pose2& command) {
  const Eigen::Vector2d end = Compose(estimate, command).Position();
  const double slack = SegmentSlack(s.grid, estimate.Position(), end);
  if (s.scenario == Scenario::kOpenLoop && slack < s.config.open_loop_margin) {
    const char* leg = "open loop: the next planned leg, from the estimated pose, would ";
    Finish(s, Outcome::kStopped,
           std::string(leg) +
               (slack < 0.0 ? "cross an obstacle"
                            : Format("keep only %.1f cm beyond the robot's radius from an obstacle "
                                     "(open_loop_margin %.1f cm)",
                                     100.0 * slack, 100.0 * s.config.open_loop_margin)));
    return false;
  }
  // A robot standing inside its clearance may walk a leg that comes no nearer an obstacle than it
  // stands (stepping out, PlanPath); any other leg must keep the clearance. Within half a cell:
  // the grid's clearance is a lower bound by up to a cell's diagonal, and the planner checks its
  // legs between cell centres, not from the exact start.
  const double tolerance = 0.5 * s.grid.resolution;
  if (slack < std::min(0.0, s.grid.Slack(estimate.Position())) - tolerance) {
    if (s.replanned_at && *s.replanned_at == time) {  // a new plan would be this one again
      Finish(s, Outcome::kStopped,
             Format("the first leg of the plan just made crosses the clearance (%.1f cm of slack)", 100.0 * slack));
      s.blocked = true;
      return false;
    }
    s.replanned_at = time;
    if (!Replan(s, estimate, false)) return false;
    PathStep(s, time, estimate);  // at the start of the new plan; bounded by max_replans
    return false;
  }
  s.robot->MoveTo(command.x, command.y, command.theta);
  s.still_since.reset();
  return true;
}

// Path phase: record an arrival, then command the leg to the next control point, P-corrected.
void PathStep(State& s, double time, const Pose2& estimate) {
  if (s.command_complete || s.scenario == Scenario::kOpenLoop) {  // open loop: nothing to redo
    Record(s, time, estimate, s.target, s.control_points[s.target], Phase::kPath);
    if (s.target + 1 >= static_cast<int>(s.control_points.size())) {
      Finish(s, Outcome::kReached, "arrived at the last control point, " + s.goal_name);
      return;
    }
    ++s.target;
  }
  const Pose2& to = s.control_points[s.target];
  Pose2 command = s.scenario == Scenario::kOpenLoop ? s.legs[s.target] : Pose2{};
  bool clamped = false;
  if (s.scenario != Scenario::kOpenLoop) {
    const Pose2 reference = NearestOnLeg(s.control_points[s.target - 1], to, estimate);
    const Pose2 error = Between(estimate, reference);  // reference seen from the robot
    const Pose2 correction{s.config.k_position * error.x, s.config.k_position * error.y,
                           s.config.k_heading * error.theta};
    command = Compose(correction, Between(reference, to));
    clamped = Clamp(s.config, &command);
  }
  s.command_complete = !clamped;
  Issue(s, time, estimate, command);
}

// Scenario 3's last part: P steps on the pose relative to the object-derived pre-grasp pose.
void ApproachStep(State& s, double time, const Pose2& estimate, bool record) {
  const Pose2 goal = TrackObject(s);
  const Pose2 offset = Between(estimate, goal);
  if (record) Record(s, time, estimate, s.records.back().index + 1, goal, Phase::kApproach);
  const double distance = offset.Position().norm(), angle = std::abs(offset.theta);
  if (distance <= s.config.approach_position_tolerance &&
      angle <= s.config.approach_heading_tolerance_deg * kDeg) {
    Finish(s, Outcome::kReached,
           "at the pre-grasp pose after " + std::to_string(s.approach_steps) + " approach steps");
    return;
  }
  if (s.approach_steps >= s.config.approach_steps_max) {
    Finish(s, Outcome::kStopped,
           Format("approach_steps_max reached %.1f cm and %.1f deg from the pre-grasp pose", 100.0 * distance,
                  angle / kDeg));
    return;
  }
  Pose2 command{s.config.k_distance * offset.x, s.config.k_distance * offset.y,
                s.config.k_angle * offset.theta};
  Clamp(s.config, &command);
  if (Issue(s, time, estimate, command)) ++s.approach_steps;
}

// Scenario 3 turns to the object after path_following_points control points, with little path
// left, or at the last control point; when the object's pre-grasp pose is within
// approach_max_distance and the straight leg to it is free.
bool ShouldApproach(State& s, const Pose2& estimate) {
  if (s.scenario != Scenario::kObjectApproach) return false;
  double remaining = 0.0;
  for (size_t k = s.target + 1; k < s.control_points.size(); ++k) {
    remaining += (s.control_points[k].Position() - s.control_points[k - 1].Position()).norm();
  }
  const bool last = s.target + 1 >= static_cast<int>(s.control_points.size());
  if (s.target < s.config.path_following_points && remaining > s.config.approach_switch_distance && !last)
    return false;
  const Footprint planned_footprint = s.grid.target_footprint;
  const GraspTarget planned_target = s.grid.target;
  const Pose2 goal = TrackObject(s);
  const bool near = last || (goal.Position() - estimate.Position()).norm() <= s.config.approach_max_distance;
  if (near && SegmentFree(s.grid, estimate.Position(), goal.Position())) return true;
  s.grid.target_footprint = planned_footprint;  // staying on the path: its legs are checked
  s.grid.target = planned_target;               // against the plan's target
  return false;
}

// At a stop: the grid from the current map, the target kept as planned (its faces then and seen
// since are its own). Obstacles seen only on the way (a bench's seat, edge-on from the start) enter it;
// whether the rest of the path crosses one. The leg now walked is Issue's to check.
bool PathBlockedByNewObstacles(State& s, const Pose2& estimate, const PlaneMap& map) {
  PlaneMap fresh = map;
  if (s.object_index >= 0) {
    if (s.object_index >= static_cast<int>(fresh.objects.size())) return false;  // keep the plan's grid
    MapObject planned = s.map.objects[s.object_index];  // its faces then and now: a moved box left its old ones
    for (int id : fresh.objects[s.object_index].landmarks) {
      if (std::find(planned.landmarks.begin(), planned.landmarks.end(), id) == planned.landmarks.end())
        planned.landmarks.push_back(id);
    }
    fresh.objects[s.object_index] = std::move(planned);
    // What appeared near the target since the plan may be the target, moved (moved_target_zone).
    const Footprint target = FootprintOf(fresh.objects[s.object_index]);
    const double zone = s.config.moved_target_zone;
    for (size_t k = s.planned_landmarks; k < fresh.landmarks.size(); ++k) {
      std::vector<Eigen::Vector3f>& points = fresh.landmarks[k].points;
      const bool near = std::any_of(points.begin(), points.end(), [&](const Eigen::Vector3f& p) {
        return target.Distance(p.head<2>().cast<double>()) <= zone;
      });
      if (near) points.clear();
    }
    for (size_t k = fresh.objects.size(); k-- > std::max<size_t>(s.planned_objects, s.object_index + 1);) {
      if (target.Distance(fresh.objects[k].center.head<2>()) <= zone) fresh.objects.erase(fresh.objects.begin() + k);
    }
  }
  OccupancyGrid grid = BuildOccupancyGrid(fresh, s.planner, {s.object_index, s.pre_grasp}, estimate.Position());
  if (grid.Empty()) return false;  // no floor in the map: keep the plan's grid
  s.map = std::move(fresh);
  s.grid = std::move(grid);
  if (s.phase != Phase::kPath) return false;
  for (size_t k = s.target + 1; k < s.control_points.size(); ++k) {
    if (SegmentSlack(s.grid, s.control_points[k - 1].Position(), s.control_points[k].Position()) < 0.0) return true;
  }
  return false;
}

// At a stop, settled, with a fresh estimate.
void Act(State& s, double time, const Pose2& estimate, const PlaneMap* map) {
  const bool blocked = map != nullptr && PathBlockedByNewObstacles(s, estimate, *map);
  if (s.retarget || blocked) {
    const bool retarget = s.retarget;
    s.retarget = false;
    if (!Replan(s, estimate, retarget)) return;
  }
  if (s.phase == Phase::kApproach) return ApproachStep(s, time, estimate, true);
  if (s.command_complete && ShouldApproach(s, estimate)) {
    Record(s, time, estimate, s.target, s.control_points[s.target], Phase::kPath);
    s.phase = Phase::kApproach;
    return ApproachStep(s, time, estimate, false);
  }
  PathStep(s, time, estimate);
}

// Stops the robot after lost_timeout without an estimate. Standing still settle_time, the robot
// turns on the spot (recovery_turn_deg) to bring mapped structure into view: a camera that sees
// only the floor of a large room, or a wall close up, shows the tracker nothing that fixes a
// heading, and a robot standing there would see nothing else. The mission ends once
// give_up_timeout has passed and recovery_turns_max turns found no pose. Whether the robot is to
// wait.
bool HandleLost(State& s, double time) {
  const double since = time - s.last_estimate_time.value_or(*s.first_time);
  if (since <= s.config.lost_timeout) {
    s.lost = false;
    s.recovery_turns = 0;
    return false;
  }
  if (!s.lost) {
    if (s.robot->IsWalking()) {
      s.robot->Stop();
      s.command_complete = false;
    }
    s.still_since.reset();  // it looks from where it stopped before it turns
  }
  s.lost = true;
  if (s.robot->IsWalking()) {
    s.still_since.reset();
    return true;
  }
  if (!s.still_since) s.still_since = time;
  if (time - *s.still_since < s.config.settle_time) return true;
  if (s.recovery_turns < s.config.recovery_turns_max) {
    ++s.recovery_turns;
    s.robot->MoveTo(0.0, 0.0, s.config.recovery_turn_deg * kDeg);
    s.still_since.reset();
    return true;
  }
  if (since > s.config.give_up_timeout) {
    Finish(s, Outcome::kStopped,
           Format("no pose estimate for %.1f s (give_up_timeout %.1f s)", since, s.config.give_up_timeout) +
               " after turning on the spot " + std::to_string(s.recovery_turns) +
               " times (mission.recovery_turns_max)");
  }
  return true;
}

// Keeps the object's latest estimate; when it has stayed moved or turned beyond the thresholds for object_moved_time
// (one noisy frame is no move), stops the robot and re-targets at the next stop: the walk in
// progress may lead into where the object now is.
void WatchObject(State& s, double time, const MapObject& object) {
  s.object = object;
  const double turn = QuarterTurn(s.planned_axes, object.axes);
  if ((object.center.head<2>() - s.planned_center).norm() <= s.config.object_moved_threshold &&
      std::abs(turn) <= s.config.object_turned_threshold_deg * kDeg) {
    s.moved_since.reset();
    return;
  }
  if (!s.moved_since) s.moved_since = time;
  if (s.retarget || time - *s.moved_since < s.config.object_moved_time) return;
  s.retarget = true;
  if (s.robot->IsWalking()) {
    s.robot->Stop();
    s.command_complete = false;
  }
}

// A new plan starts a new run, with the same settings.
void Reset(std::unique_ptr<MissionState>& state) {
  MissionState fresh;
  fresh.scenario = state->scenario;
  fresh.config = state->config;
  fresh.planner = state->planner;
  fresh.grasp = state->grasp;
  fresh.robot = state->robot;
  *state = std::move(fresh);
}

// Scenario 1's legs between the control points, computed in advance.
void MakeLegs(State& s) {
  s.legs.assign(s.control_points.size(), Pose2{});
  for (size_t k = 1; k < s.control_points.size(); ++k)
    s.legs[k] = Between(s.control_points[k - 1], s.control_points[k]);
}

}  // namespace

Mission::Mission(Scenario scenario, const MissionConfig& config, const PlannerConfig& planner,
                 const GraspConfig& grasp, Humanoid* robot)
    : state_(std::make_unique<MissionState>()) {
  ValidateConfig(config, "mission.");
  ValidateConfig(planner, "planner.");
  ValidateConfig(grasp, "grasp.");
  if (planner.final_leg_radius >= grasp.body_clearance) {
    throw std::invalid_argument("planner.final_leg_radius (" + std::to_string(planner.final_leg_radius) +
                                " m) must be below grasp.body_clearance (" + std::to_string(grasp.body_clearance) +
                                " m): a pre-grasp pose that close to its box would count as blocked");
  }
  state_->scenario = scenario;
  state_->config = config;
  state_->planner = planner;
  state_->grasp = grasp;
  state_->robot = robot;
}

Mission::~Mission() = default;

PlanResult Mission::Plan(const PlaneMap& map, int object_index, const Pose2& start_estimate) {
  Reset(state_);
  MissionState& s = *state_;
  PlanResult failure;
  if (object_index < 0 || object_index >= static_cast<int>(map.objects.size())) {
    failure.reason = "object " + std::to_string(object_index) + " is not in the map (" +
                     std::to_string(map.objects.size()) + " objects)";
    return failure;
  }
  s.map = map;
  s.object_index = object_index;
  s.object = map.objects[object_index];
  // Every side the hands can span, the preferred first (ChooseGraspSide's order): a side whose
  // pre-grasp pose no path reaches (a box by a wall, in a corner) gives way to the next.
  const Eigen::Vector2d toward_robot = start_estimate.Position() - s.object.center.head<2>();
  std::vector<Eigen::Vector2d> sides = GraspSides(s.object, s.grasp, toward_robot);
  if (sides.empty()) sides.push_back(ChooseGraspSide(s.object, s.grasp, toward_robot));  // fails the check, with its reason
  PlanResult first_failure;
  for (size_t k = 0; k < sides.size(); ++k) {
    Retarget(s, start_estimate, sides[k]);
    const GraspCheck check = CheckGrasp(Grasped(s), s.pre_grasp, s.grasp);
    if (!check.ok) {
      failure.reason = "object " + std::to_string(object_index) +
                       " cannot be grasped from its pre-grasp pose: " + check.reason;
      if (first_failure.reason.empty()) first_failure = failure;
      continue;
    }
    PlanResult result = MakePlan(s, start_estimate);
    if (!result.ok) {
      if (first_failure.reason.empty()) first_failure = result;
      continue;
    }
    MakeLegs(s);
    s.status = {Outcome::kRunning, "walking to the pre-grasp pose"};
    return result;
  }
  Reset(state_);
  return first_failure;
}

PlanResult Mission::PlanTo(const PlaneMap& map, const Pose2& goal, const Pose2& start_estimate) {
  Reset(state_);
  MissionState& s = *state_;
  s.map = map;
  s.pre_grasp = goal;
  s.goal_name = "the viewpoint";
  PlanResult result = MakePlan(s, start_estimate);
  if (!result.ok) return result;
  MakeLegs(s);
  s.status = {Outcome::kRunning, "walking to the viewpoint"};
  return result;
}

void Mission::Update(double time, const std::optional<Pose2>& estimate, const MapObject* object_estimate,
                     const PlaneMap* map) {
  MissionState& s = *state_;
  if (s.status.outcome != Outcome::kRunning) return;
  if (!s.first_time) s.first_time = time;
  if (estimate) s.last_estimate_time = time;
  if (object_estimate != nullptr && s.scenario != Scenario::kOpenLoop) WatchObject(s, time, *object_estimate);
  if (HandleLost(s, time)) return;
  if (s.robot->IsWalking()) {
    s.still_since.reset();
    return;
  }
  if (!s.still_since) s.still_since = time;
  if (time - *s.still_since >= s.config.settle_time && estimate) Act(s, time, *estimate, map);
}

void Mission::GiveUp(const std::string& reason) {
  MissionState& s = *state_;
  if (s.status.outcome != Outcome::kRunning) return;
  Finish(s, Outcome::kStopped, reason);
  s.blocked = true;
}

bool Mission::Done() const {
  return Status().outcome == Outcome::kReached || Status().outcome == Outcome::kStopped;
}
bool Mission::Blocked() const { return state_->blocked; }
MissionStatus Mission::Status() const { return state_->status; }
const std::vector<ControlPointRecord>& Mission::Records() const { return state_->records; }
const std::vector<Pose2>& Mission::ReferencePath() const { return state_->path; }
const std::vector<Pose2>& Mission::ControlPoints() const { return state_->control_points; }
Pose2 Mission::PreGraspTarget() const { return state_->pre_grasp; }
Eigen::Vector2d Mission::GraspSide() const { return state_->grasp_axis; }
const OccupancyGrid& Mission::Grid() const { return state_->grid; }
int Mission::Replans() const { return state_->replans; }

double DistanceToPath(const std::vector<Pose2>& path, const Eigen::Vector2d& p) {
  if (path.empty()) return std::numeric_limits<double>::infinity();
  double best = (p - path.front().Position()).norm();
  for (size_t k = 1; k < path.size(); ++k) {
    const Eigen::Vector2d a = path[k - 1].Position(), d = path[k].Position() - a;
    const double t = d.squaredNorm() < 1e-18 ? 0.0 : std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (p - a - t * d).norm());
  }
  return best;
}

}  // namespace planemap::nav
