// The closed loop of `planemap approach`: render, perceive, estimate, control, walk.
#include "planemap/apps/approach.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include <yaml-cpp/yaml.h>

#include "planemap/apps/app_config.h"
#include "planemap/backend/backend.h"
#include "planemap/core/error.h"
#include "planemap/nav/simulated_humanoid.h"
#include "planemap/nav/target.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/virtual_camera.h"
#include "planemap/pipeline/mapper.h"

namespace planemap {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kDegToRad = M_PI / 180.0;

double Ms(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }

std::string Seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f s", s);
  return text;
}

// The scene with one object moved by (dx, dy) [m] and turned by dyaw [deg]: the scene file's
// contents edited and parsed again, so the moved object's surfaces are built as any scene's are.
sim::Scene MovedScene(const YAML::Node& scene_yaml, const std::string& file, const std::string& object,
                      const std::vector<double>& by) {
  YAML::Node root = YAML::Clone(scene_yaml);
  bool found = false;
  for (YAML::Node o : root["objects"]) {
    if (o["name"].as<std::string>() != object) continue;
    YAML::Node position = o["position"], rpy = o["rpy_deg"];
    position[0] = position[0].as<double>() + by[0];
    position[1] = position[1].as<double>() + by[1];
    if (rpy) rpy[2] = rpy[2].as<double>() + by[2];
    found = true;
  }
  if (!found) ThrowInputError(file, 0, "no object named '" + object + "' to move");
  return sim::ParseScene(root, file + " (object " + object + " moved)");
}

// The scene object as the map would hold it, grasped from the true face nearest the estimate's
// grasp axis (scoring asks: how far is the robot from where it should stand for that face).
MapObject TrueObject(const sim::SceneObject& o, const Eigen::Vector3d& estimated_grasp_axis) {
  MapObject m;
  m.label = o.type;
  m.center = o.Center();
  m.axes = o.T_world_object.linear();
  m.dimensions = o.dimensions;
  double best = -2.0;
  for (int k = 0; k < 2; ++k) {
    for (double side : {1.0, -1.0}) {
      const Eigen::Vector3d axis = side * m.axes.col(k);
      if (axis.dot(estimated_grasp_axis) > best) {
        best = axis.dot(estimated_grasp_axis);
        m.grasp_axis = axis;
      }
    }
  }
  m.has_grasp_axis = true;
  return m;
}

// The mapped objects of the target's class and size (nav/target.h) seen in min_observations
// frames or more that the arms could grasp from their pre-grasp pose (as Mission::Plan checks
// it), the most seen first. `ungraspable`: how many could not be, and why the last could not;
// `unconfirmed`: how many were seen in fewer frames (one view of a wall 5 m away can make a
// "box"); `other_size`: how many of the class were measured at another size, and the last one's.
struct TargetCounts {
  int ungraspable = 0, unconfirmed = 0, other_size = 0;
  std::string ungraspable_why, other_size_why;
};

std::vector<int> FindTargets(const PlaneMap& map, const nav::TargetDescription& target, const nav::GraspConfig& grasp,
                             int min_observations, const nav::Pose2& robot, TargetCounts* counts) {
  std::vector<int> targets;
  *counts = TargetCounts{};
  for (const MapObject& o : map.objects) {
    if (o.structure || o.label != target.label) continue;
    if (const std::string conflict = nav::SizeConflict(o, target); !conflict.empty()) {
      ++counts->other_size;
      counts->other_size_why = "object " + std::to_string(o.id) + ": " + conflict;
      continue;
    }
    if (o.observations < min_observations) {
      ++counts->unconfirmed;
      continue;
    }
    const Eigen::Vector2d side = nav::ChooseGraspSide(o, grasp, robot.Position() - o.center.head<2>());
    const nav::GraspCheck check = nav::CheckGrasp(o, nav::PreGraspPose(o, grasp, side), grasp);
    if (!check.ok) {
      ++counts->ungraspable;
      counts->ungraspable_why = check.reason;
      continue;
    }
    targets.push_back(o.id);
  }
  std::stable_sort(targets.begin(), targets.end(),
                   [&](int a, int b) { return map.objects[a].observations > map.objects[b].observations; });
  return targets;
}

// The scene object whose centre is nearest (on the floor) to a point.
const sim::SceneObject& NearestObject(const sim::Scene& scene, const Eigen::Vector3d& p) {
  const sim::SceneObject* best = &scene.objects.front();
  for (const sim::SceneObject& o : scene.objects) {
    if ((o.Center() - p).head<2>().norm() < (best->Center() - p).head<2>().norm()) best = &o;
  }
  return *best;
}

// The map with the latest frame's planes added as landmarks seen `observations` times, in the
// world by the estimated camera pose: faces too far or too uncertain for the tracker to map (a
// box 2.7 m away) are still faces the search may look at again.
PlaneMap WithFacesInView(PlaneMap map, const FrameModel& model, const Cloud& cloud,
                         const Pose3& T_world_camera, int observations) {
  for (const DetectedPlane& p : model.planes) {
    if (p.id == model.floor) continue;
    PlaneLandmark l;
    l.id = static_cast<int>(map.landmarks.size());
    l.plane = TransformPlane(T_world_camera, p.plane);
    l.observations = observations;
    const size_t stride = std::max<size_t>(1, p.inliers.size() / 200);
    for (size_t k = 0; k < p.inliers.size(); k += stride) {
      const Eigen::Vector3d x = T_world_camera * cloud[p.inliers[k]].getVector3fMap().cast<double>();
      l.points.push_back(x.cast<float>());
    }
    map.landmarks.push_back(std::move(l));
  }
  return map;
}

}  // namespace

// A humanoid walks under a table's top between its legs
// (the planner, whose obstacles end at planner.max_obstacle_height, plans such paths), so the
// object's bounding box would count a collision where there is none.
std::vector<std::pair<std::string, nav::Footprint>> CollisionFootprints(const sim::Scene& scene, double body_height) {
  std::vector<std::pair<std::string, nav::Footprint>> footprints;
  for (const sim::SceneObject& o : scene.objects) {
    for (size_t index : o.cuboids) {
      const sim::Cuboid& c = scene.cuboids.at(index);
      const double underside = c.T_world_box.translation().z() - 0.5 * c.T_world_box.linear().row(2).cwiseAbs().dot(c.dimensions);
      if (underside >= body_height) continue;
      MapObject part;
      part.center = c.T_world_box.translation();
      part.axes = c.T_world_box.linear();
      part.dimensions = c.dimensions;
      footprints.emplace_back(o.name, nav::FootprintOf(part));
    }
  }
  return footprints;
}

struct ApproachInputs {
  std::string scene_file;
  YAML::Node scene_yaml;  // the file's contents, for moving an object
  sim::Scene scene;
  CameraIntrinsics camera;
  AppConfig config;
  PatternsConfig patterns;
};

std::shared_ptr<const ApproachInputs> LoadApproachInputs(const ApproachOptions& options) {
  auto inputs = std::make_shared<ApproachInputs>();
  inputs->scene_file = ResolveConfigPath(options.scene);
  inputs->scene_yaml = LoadYamlFile(inputs->scene_file);
  inputs->scene = sim::ParseScene(inputs->scene_yaml, inputs->scene_file);
  if (inputs->scene.objects.empty())
    ThrowInputError(inputs->scene_file, 0, "the scene has no objects to approach");
  inputs->camera = LoadCameraIntrinsics(ResolveConfigPath(options.camera));
  inputs->config = LoadConfigFile<AppConfig>(ResolveConfigPath(options.config));
  inputs->patterns = LoadPatterns(ResolveConfigPath(options.patterns));
  return inputs;
}

ApproachRun RunApproachOnce(const ApproachOptions& options) {
  return RunApproachOnce(options, *LoadApproachInputs(options));
}

ApproachRun RunApproachOnce(const ApproachOptions& options, const ApproachInputs& inputs) {
  if (options.scenario < 1 || options.scenario > 3) throw InputError("--scenario must be 1, 2 or 3");
  if (options.start.size() != 3) throw InputError("--start needs x y heading_deg");
  if (options.move_object_by.size() != 3) throw InputError("--move-by needs dx dy dyaw_deg");
  const auto finite = [](const std::vector<double>& v) { return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }); };
  if (!finite(options.start)) throw InputError("--start needs finite numbers: x y [m] heading [deg]");
  if (!finite(options.move_object_by)) throw InputError("--move-by needs finite numbers: dx dy [m] dyaw [deg]");
  // Every frame is rendered and processed: past a kilohertz the run would take days of frames.
  if (!(options.rate > 0.0) || !(options.rate <= 1000.0)) throw InputError("--rate must be a positive number up to 1000 [Hz]");
  if (!(options.max_time > 0.0) || !std::isfinite(options.max_time)) throw InputError("--max-time must be a positive number [s]");
  if (!finite({options.move_object_at, options.drop_at})) throw InputError("--move-object-at and --drop-at must be finite [s]");
  if (!(options.drop_duration >= 0.0) || !std::isfinite(options.drop_duration)) throw InputError("--drop-for must be a number >= 0 [s]");
  if (options.seed < 0) throw InputError("--seed must be 0 or more");
  if (!options.target_size.empty() &&
      (options.target_size.size() != 3 ||
       std::any_of(options.target_size.begin(), options.target_size.end(), [](double v) { return !(v > 0.0); })))
    throw InputError("--target-size needs 3 positive numbers: the two horizontal extents and the height [m]");
  const sim::Scene& scene = inputs.scene;
  const CameraIntrinsics& camera = inputs.camera;
  AppConfig config = inputs.config;
  config.render.seed = options.seed;
  // What the robot is told to fetch: the class, and the size given, or the scene task's box's.
  nav::TargetDescription wanted{options.target, std::nullopt, config.search.target_size_tolerance};
  if (options.target_size.size() == 3) {
    wanted.size = Eigen::Vector3d(options.target_size[0], options.target_size[1], options.target_size[2]);
  } else if (!scene.task_object.empty()) {
    wanted.size = scene.object(scene.task_object).dimensions;
  }
  const sim::VirtualCamera sensor(scene, camera, config.render);
  std::unique_ptr<sim::VirtualCamera> moved_sensor;  // built when the target is known

  const nav::Pose2 start{options.start[0], options.start[1], options.start[2] * kDegToRad};
  nav::SimulatedHumanoid robot(config.humanoid, start, static_cast<std::uint64_t>(options.seed));
  nav::OdometryCalibration odometry(config.odometry_calibration);
  // The robot knows where it starts (the paper: from the first frames; here the world is the
  // scene's, as `planemap map` anchors a sequence with ground truth).
  Mapper mapper(camera, config.mapper(), inputs.patterns, robot.CameraPose());
  nav::Mission mission(static_cast<nav::Scenario>(options.scenario), config.mission, config.planner, config.grasp, &robot);
  nav::Search search(config.search, config.mission, config.planner, config.grasp, &robot);
  double view_start = 0.0;  // when the robot began standing at the start or at its last viewpoint [s]
  int plans_given_up = 0;   // plans left for want of a way on, or whose target proved another (Mission::Blocked)
  double ruled_out_since = -1.0;  // since when the map rules the planned target out [s]; -1: it does not
  FrameModel last_model;     // the last frame processed, and its cloud and camera pose estimate
  Cloud::Ptr last_cloud;
  Pose3 last_T_world_camera = Pose3::Identity();

  ApproachRun run;
  run.scenario = options.scenario;
  run.seed = options.seed;
  const sim::SceneObject* target_truth = nullptr;
  std::vector<std::pair<std::string, nav::Footprint>> footprints = CollisionFootprints(scene, options.body_height);
  sim::Scene moved_scene;
  bool moved = false;
  int target = -1;
  double last_estimate_time = 0.0;  // the last frame with a pose estimate (the start pose is known) [s]
  std::string track_reason;         // why the last frame without one had none
  const double dt = 1.0 / options.rate;
  for (int k = 0;; ++k) {
    const double t = k * dt;
    if (t > options.max_time) {
      run.status.outcome = nav::MissionStatus::Outcome::kStopped;
      run.status.reason = "out of time after " + Seconds(options.max_time);
      break;
    }
    if (!moved && target_truth && options.move_object_at >= 0.0 && t >= options.move_object_at) {
      moved_scene =
          MovedScene(inputs.scene_yaml, inputs.scene_file, target_truth->name, options.move_object_by);
      moved_sensor = std::make_unique<sim::VirtualCamera>(moved_scene, camera, config.render);
      target_truth = &moved_scene.object(target_truth->name);
      footprints = CollisionFootprints(moved_scene, options.body_height);
      moved = true;
    }
    const bool dropped = options.drop_at >= 0.0 && t >= options.drop_at && t < options.drop_at + options.drop_duration;
    std::optional<nav::Pose2> estimate;
    ++run.frames;
    ApproachFrame& traced = run.trace.emplace_back();
    traced.time = t;
    traced.phase = !run.planned ? (search.Walking() ? "search" : "look")
                   : mission.Records().empty() || mission.Records().back().phase == nav::Phase::kPath ? "path"
                                                                                                      : "approach";
    traced.truth = robot.TruePose();
    if (dropped) {
      traced.status = "dropped";
      ++run.lost_frames;
      track_reason = "lost: the frame dropped out";
      odometry.Correct(robot.OdometryPose());
      odometry.Observe(std::nullopt);
    } else {
      const auto t0 = Clock::now();
      const sim::VirtualCamera& cam = moved ? *moved_sensor : sensor;
      sim::RenderedFrame rendered = cam.Render(robot.CameraPose(), cam.FrameSeed(k));
      RgbdFrame frame;
      frame.depth = std::move(rendered.depth);
      frame.color = std::move(rendered.color);
      frame.stamp = t;
      const auto t1 = Clock::now();
      Perception perception = mapper.Perceive(frame);
      const auto t2 = Clock::now();
      const nav::Pose2 odometry_pose = odometry.Correct(robot.OdometryPose());
      const MapperStep step = mapper.Track(perception, t, nav::NominalCameraPose(odometry_pose, config.humanoid));
      const TrackResult& tracked = step.track;
      // Only a pose the planes fixed in every direction measures the gait.
      std::optional<nav::Pose2> measured;
      if (tracked.status == TrackStatus::kTracked)
        measured = nav::BaseFromCamera(tracked.T_world_camera, config.humanoid.camera_forward_offset);
      odometry.Observe(measured);
      if (!run.planned) {  // for the search (moved: the frame is done with it)
        last_model = std::move(perception.model);
        last_cloud = perception.cloud;
        last_T_world_camera = step.T_world_camera_smoothed;
      }
      const auto t3 = Clock::now();
      run.render_ms.push_back(Ms(t0, t1));
      run.perception_ms.push_back(Ms(t1, t2));
      run.estimation_ms.push_back(Ms(t2, t3));
      traced.status = ToString(tracked.status);
      traced.planes = tracked.planes;
      traced.matched = tracked.matched;
      traced.inliers = tracked.inliers;
      traced.added = tracked.added;
      traced.refined = tracked.refined;
      traced.reason = tracked.reason;
      traced.tracked = nav::BaseFromCamera(tracked.T_world_camera, config.humanoid.camera_forward_offset);
      if (tracked.status == TrackStatus::kLost) {
        ++run.lost_frames;
        track_reason = "lost: " + tracked.reason;
      } else {
        last_estimate_time = t;
        estimate = nav::BaseFromCamera(step.T_world_camera_smoothed, config.humanoid.camera_forward_offset);
        traced.has_estimate = true;
        traced.estimate = *estimate;
        run.estimate_path.push_back(*estimate);
        run.pose_errors.push_back((estimate->Position() - robot.TruePose().Position()).norm());
      }
    }
    run.truth_path.push_back(robot.TruePose());

    // Plan once the robot has looked around and mapped its target; without one, look again
    // from a viewpoint (nav::Search), walked to with path feedback in every scenario.
    if (!run.planned && search.Walking()) {
      search.Update(t, estimate, &mapper.map());
      if (!search.Walking()) {
        if (!search.Status().Reached() && !search.GaveUpView()) {
          run.status = {nav::MissionStatus::Outcome::kStopped, "looking again: " + search.Status().reason};
          break;
        }
        view_start = t;
      }
    } else if (!run.planned && estimate && t - view_start >= options.look_time) {
      TargetCounts counts;
      std::string plan_failure;
      target = -1;
      // The most seen target a plan reaches; one whose plan fails is passed over.
      for (int candidate : FindTargets(mapper.map(), wanted, config.grasp, config.search.target_min_observations,
                                       *estimate, &counts)) {
        const nav::PlanResult plan = mission.Plan(mapper.map(), candidate, *estimate);
        if (plan.ok) {
          target = candidate;
          break;
        }
        if (plan_failure.empty()) plan_failure = "object " + std::to_string(candidate) + ": " + plan.reason;
      }
      if (target >= 0) {
        run.planned = true;
        // Scored against the scene's task object when it names one, whatever was approached.
        const sim::SceneObject& approached = NearestObject(scene, mapper.map().objects[target].center);
        target_truth = scene.task_object.empty() ? &approached : &scene.object(scene.task_object);
        run.target = approached.name;
        run.intended = scene.task_object;
        run.reference = mission.ReferencePath();
        run.pregrasp_planned = mission.PreGraspTarget();
      } else if (t - view_start >=
                 (search.Viewpoints().empty() ? options.look_timeout : config.search.look_time)) {
        std::string why;
        const PlaneMap seen = last_cloud ? WithFacesInView(mapper.map(), last_model, *last_cloud,
                                                            last_T_world_camera,
                                                            config.search.candidate_min_observations)
                                         : mapper.map();
        if (!search.Next(seen, *estimate, wanted, &why)) {
          std::string none = counts.ungraspable > 0 ? "no " + options.target + " the arms can grasp (" +
                                                          std::to_string(counts.ungraspable) + " mapped; " +
                                                          counts.ungraspable_why + ")"
                                                    : "no " + options.target + " in the map";
          if (!plan_failure.empty()) none = "no " + options.target + " a plan reaches (" + plan_failure + ")";
          if (counts.other_size > 0)
            none += " (" + std::to_string(counts.other_size) + " of another size; " + counts.other_size_why + ")";
          if (counts.unconfirmed > 0)
            none += " (" + std::to_string(counts.unconfirmed) +
                    " seen in fewer than search.target_min_observations frames)";
          run.status = {nav::MissionStatus::Outcome::kStopped,
                        none + " after " + Seconds(t) + " of looking; " + why};
          break;
        }
        run.viewpoints = search.Viewpoints();
      }
    } else if (!run.planned && !estimate && t - last_estimate_time > config.mission.give_up_timeout) {
      // Standing, lost, before any plan: the search and the mission both need a pose.
      run.status = {nav::MissionStatus::Outcome::kStopped,
                    "no pose estimate for " + Seconds(t - last_estimate_time) +
                        " before planning (mission.give_up_timeout): tracking " + track_reason};
      break;
    }
    if (run.planned) {
      const size_t before = mission.Records().size();
      const auto t4 = Clock::now();
      const MapObject* object = target >= 0 && target < static_cast<int>(mapper.map().objects.size()) ? &mapper.map().objects[target] : nullptr;
      mission.Update(t, estimate, object, &mapper.map());
      // The target was chosen while some of its dimensions were only bounded (a face cut by the
      // image or by what stands before it); seen on the way, it may prove another size or class
      // (a bench's slab leg, first taken for a box seen edge-on). Once that has held for
      // object_moved_time (one noisy frame is no measurement), the plan is given up and the robot
      // chooses again.
      if (object != nullptr && !mission.Done() && nav::RuledOut(*object, wanted)) {
        if (ruled_out_since < 0.0) ruled_out_since = t;
        if (t - ruled_out_since >= config.mission.object_moved_time) {
          const std::string conflict = nav::SizeConflict(*object, wanted);
          mission.GiveUp("object " + std::to_string(target) + " proved not the target on the way: " +
                         (conflict.empty() ? "a " + object->label + " with its height measured" : conflict));
        }
      } else {
        ruled_out_since = -1.0;
      }
      run.control_ms.push_back(Ms(t4, Clock::now()));
      for (size_t i = before; i < mission.Records().size(); ++i) {
        const nav::Pose2 truth = robot.TruePose();
        run.stops.push_back({mission.Records()[i], truth, nav::DistanceToPath(mission.ReferencePath(), truth.Position())});
      }
      // A plan that an obstacle seen on the way leaves without a way on (its goal blocked, say) is
      // given up, and the robot chooses again from where it stands: another side of the box, or
      // another box (mission.max_replans such plans at most).
      if (mission.Done() && mission.Blocked() && plans_given_up < config.mission.max_replans) {
        ++plans_given_up;
        ruled_out_since = -1.0;
        run.planned = false;
        target = -1;
        view_start = t;
      } else if (mission.Done()) {
        run.status = mission.Status();
        break;
      }
    }
    // Collisions: the robot's true footprint against every true object.
    for (const auto& [name, footprint] : footprints) {
      if (run.collided || footprint.Distance(robot.TruePose().Position()) >= options.body_radius) continue;
      run.collided = true;
      char text[128];
      std::snprintf(text, sizeof(text), "%s at %.1f s", name.c_str(), t);
      run.collision = text;
    }
    robot.Advance(dt);
  }
  run.gait = {odometry.Scale(), odometry.Lateral(), odometry.CalibratedDistance(), robot.BiasScale(),
              robot.BiasLateral()};
  run.duration = robot.Time();
  run.reference = run.planned ? mission.ReferencePath() : run.reference;
  run.footsteps = robot.Footsteps();
  run.map = mapper.map();
  if (!scene.task_object.empty()) {
    const sim::SceneObject& truth = (moved ? moved_scene : scene).object(scene.task_object);
    const nav::Footprint footprint = nav::FootprintOf(TrueObject(truth, Eigen::Vector3d::UnitX()));
    run.task_object_mapped = std::any_of(run.map.objects.begin(), run.map.objects.end(), [&](const MapObject& o) {
      return !o.structure && footprint.Distance(o.center.head<2>()) == 0.0;
    });
  }
  if (!run.planned || !target_truth) return run;

  // Scores against ground truth: where the robot should stand for the face it chose.
  const Eigen::Vector2d g = mission.GraspSide();
  const MapObject truth_object = TrueObject(*target_truth, Eigen::Vector3d(g.x(), g.y(), 0.0));
  const nav::Pose2 final_pose = robot.TruePose();
  run.pregrasp_true = nav::PreGraspPose(truth_object, config.grasp, truth_object.grasp_axis.head<2>());
  run.position_error = (final_pose.Position() - run.pregrasp_true.Position()).norm();
  run.heading_error = std::abs(nav::WrapAngle(final_pose.theta - run.pregrasp_true.theta));
  const MapObject& estimated = mapper.map().objects[target];
  const nav::GraspGeometry faces = nav::GraspFaces(estimated, g);
  const nav::GraspGeometry true_faces = nav::GraspFaces(truth_object, g);
  run.object_center_error = (estimated.center - truth_object.center).norm();
  run.object_depth = faces.depth;
  run.object_depth_true = true_faces.depth;
  run.object_width = faces.width;
  run.object_width_true = true_faces.width;
  const nav::GraspCheck check = nav::CheckGrasp(truth_object, final_pose, config.grasp);
  run.grasp_ok = check.ok;
  run.grasp_reason = check.reason;
  double sum = 0.0;
  for (const ApproachStop& s : run.stops) sum += s.truth_to_path;
  run.average_error = run.stops.empty() ? 0.0 : sum / run.stops.size();
  return run;
}

}  // namespace planemap
