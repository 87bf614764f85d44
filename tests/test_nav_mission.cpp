// The paper's three scenarios (Table 1, Fig. 8) on a synthetic room, walked by a small test
// double of the humanoid: each MoveTo lands with a per-run bias and per-command noise. Estimates
// are the true pose plus noise; the object's estimate is the true object seen from the robot
// (accurate relative to it, as a camera sees it) placed by the estimated pose.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "planemap/nav/grasp.h"
#include "planemap/nav/humanoid.h"
#include "planemap/nav/mission.h"
#include "planemap/nav/search.h"
#include "test_support.h"

namespace planemap::nav {
namespace {

using planemap::testing::Median;
using planemap::testing::Rectangle;
constexpr double kDeg = M_PI / 180.0;
constexpr double kRate = 30.0;  // camera frames per second
const Eigen::Vector3d kX = Eigen::Vector3d::UnitX(), kY = Eigen::Vector3d::UnitY(),
                      kZ = Eigen::Vector3d::UnitZ();

struct WalkError {
  double scale = 0.0, lateral = 0.0, turn = 0.0;  // per-run bias: [-], [m/m], [rad/m]
  double noise_xy = 0.0, noise_turn = 0.0;        // per-command noise std: [m/m], [rad/(m + rad)]
};

// Walks each MoveTo in a straight interpolation at 0.1 m/s and 0.5 rad/s to where the command,
// perturbed, leads; Stop() halts where it is.
class FakeHumanoid : public Humanoid {
 public:
  FakeHumanoid(const Pose2& start, const WalkError& error, unsigned seed)
      : pose_(start), error_(error), rng_(seed) {}

  void MoveTo(double dx, double dy, double dtheta) override {
    std::normal_distribution<double> n(0.0, 1.0);
    const double d = std::hypot(dx, dy);
    const Pose2 landed{dx * (1.0 + error_.scale) + error_.noise_xy * d * n(rng_),
                       dy + error_.lateral * d + error_.noise_xy * d * n(rng_),
                       dtheta + error_.turn * d + error_.noise_turn * (d + std::abs(dtheta)) * n(rng_)};
    odometry_ = Compose(odometry_, Pose2{dx, dy, dtheta});
    from_ = pose_;
    to_ = Compose(pose_, landed);
    duration_ = std::max({d / 0.1, std::abs(landed.theta) / 0.5, 0.2});
    elapsed_ = 0.0;
    walking_ = true;
  }
  void Stop() override { walking_ = false; }
  bool IsWalking() const override { return walking_; }
  // The commands summed (the mission does not read odometry).
  Pose2 OdometryPose() const override { return odometry_; }

  void Advance(double dt) {
    if (!walking_) return;
    elapsed_ = std::min(duration_, elapsed_ + dt);
    const double s = elapsed_ / duration_;
    pose_ = {from_.x + s * (to_.x - from_.x), from_.y + s * (to_.y - from_.y),
             WrapAngle(from_.theta + s * WrapAngle(to_.theta - from_.theta))};
    if (elapsed_ >= duration_) walking_ = false;
  }
  const Pose2& TruePose() const { return pose_; }

 private:
  Pose2 pose_, from_, to_, odometry_;
  WalkError error_;
  std::mt19937 rng_;
  double duration_ = 0.0, elapsed_ = 0.0;
  bool walking_ = false;
};

MapObject Box(const Eigen::Vector3d& center, double yaw_deg, const Eigen::Vector3d& dimensions) {
  return planemap::testing::BoxObject(center, yaw_deg, dimensions, +1.0);
}

// Floor x in [-1, 3.5], y in [-2, 2]; a wall at x = 3.5; the default scene's box to grasp (its
// +x face and top as landmarks); a 30 x 30 x 40 cm crate in the way at (1, 0).
PlaneMap Room() {
  PlaneMap map;
  map.landmarks.push_back(Rectangle(0, {1.25, 0.0, 0.0}, kX, 2.25, kY, 2.0));
  map.landmarks[0].floor_votes = 1;
  map.landmarks.push_back(Rectangle(1, {3.5, 0.0, 1.0}, kZ, 1.0, kY, 2.0));
  MapObject box = Box({2.1, 0.1, 0.125}, 215.0, {0.25, 0.35, 0.25});
  const Eigen::Vector3d x = box.axes.col(0), y = box.axes.col(1);
  map.landmarks.push_back(Rectangle(2, box.center + 0.125 * x, y, 0.175, kZ, 0.125));
  map.landmarks.push_back(Rectangle(3, box.center + 0.125 * kZ, x, 0.125, y, 0.175));
  box.landmarks = {2, 3};
  map.objects.push_back(box);
  map.objects.push_back(Box({1.0, 0.0, 0.2}, 10.0, {0.3, 0.3, 0.4}));
  return map;
}

struct Trial {
  Scenario scenario = Scenario::kObjectApproach;
  WalkError walk;
  double pose_noise = 0.0, heading_noise_deg = 0.0;  // estimate = true pose + this noise (std)
  double object_noise = 0.0;                         // object centre estimate noise (std) [m]
  unsigned seed = 1;
  double lost_from = 1e9, lost_to = 1e9;                   // no estimates in [lost_from, lost_to) [s]
  // ... or, when positive, from lost_from until the robot has turned this much since [deg]
  double lost_until_turned_deg = 0.0;
  double object_moves_at = 1e9;                            // the object then moves ...
  Eigen::Vector2d object_shift = Eigen::Vector2d::Zero();  // ... by this [m]
  MissionConfig mission;
};

struct Outcome {
  MissionStatus status;
  Pose2 final_pose, true_pre_grasp, planned_pre_grasp, final_target;
  std::vector<ControlPointRecord> records;
  std::vector<Pose2> path;
  std::vector<Pose2> trajectory;  // true poses, every frame
  int replans = 0;
  bool walking_at_end = false;
  double ErrorCm() const { return 100.0 * (final_pose.Position() - true_pre_grasp.Position()).norm(); }
};

// The object as seen from the true pose, placed in the world by the estimated pose.
MapObject Seen(MapObject object, const Pose2& truth, const Pose2& estimate, double noise, std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, noise);
  const Pose2 drift = Compose(estimate, Inverse(truth));
  const Pose2 c = Compose(drift, {object.center.x(), object.center.y(), 0.0});
  object.center.head<2>() = Eigen::Vector2d(c.x + n(*rng), c.y + n(*rng));
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(drift.theta, kZ).toRotationMatrix();
  object.axes = turn * object.axes;
  object.grasp_axis = turn * object.grasp_axis;
  return object;
}

Outcome Simulate(const Trial& run) {
  const PlaneMap map = Room();
  MapObject truth = map.objects[0];
  const Pose2 start{0.0, 0.0, 0.0};
  FakeHumanoid robot(start, run.walk, run.seed);
  Mission mission(run.scenario, run.mission, PlannerConfig{}, GraspConfig{}, &robot);
  const PlanResult plan = mission.Plan(map, 0, start);
  EXPECT_TRUE(plan.ok) << plan.reason;
  Outcome out;
  out.planned_pre_grasp = mission.PreGraspTarget();
  std::mt19937 rng(1000 + run.seed);
  std::normal_distribution<double> n(0.0, 1.0);
  double turned_since_lost = 0.0, last_heading = start.theta;  // [rad]
  for (int frame = 0; frame < 200 * kRate && !mission.Done(); ++frame) {
    const double t = frame / kRate;
    if (t >= run.object_moves_at) truth.center.head<2>() = map.objects[0].center.head<2>() + run.object_shift;
    if (t >= run.lost_from) turned_since_lost += std::abs(WrapAngle(robot.TruePose().theta - last_heading));
    last_heading = robot.TruePose().theta;
    const bool blind = run.lost_until_turned_deg > 0.0
                           ? t >= run.lost_from && turned_since_lost < run.lost_until_turned_deg * kDeg
                           : t >= run.lost_from && t < run.lost_to;
    std::optional<Pose2> estimate;
    MapObject seen;
    if (!blind) {
      const Pose2 noise{run.pose_noise * n(rng), run.pose_noise * n(rng),
                        run.heading_noise_deg * kDeg * n(rng)};
      estimate = Compose(robot.TruePose(), noise);
      seen = Seen(truth, robot.TruePose(), *estimate, run.object_noise, &rng);
    }
    mission.Update(t, estimate, estimate ? &seen : nullptr);
    robot.Advance(1.0 / kRate);
    out.trajectory.push_back(robot.TruePose());
  }
  out.status = mission.Status();
  out.final_pose = robot.TruePose();
  out.true_pre_grasp = PreGraspPose(truth, GraspConfig{}, -truth.center.head<2>());
  out.final_target = mission.PreGraspTarget();
  out.records = mission.Records();
  out.path = mission.ReferencePath();
  out.replans = mission.Replans();
  out.walking_at_end = robot.IsWalking();
  return out;
}

// A walker that drifts: per-run biases drawn from the seed, as a real gait's.
WalkError Drifting(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  WalkError e;
  e.scale = 0.04 * n(rng);
  e.lateral = 0.05 * n(rng);
  e.turn = 0.06 * n(rng);
  e.noise_xy = 0.03;
  e.noise_turn = 0.02;
  return e;
}

class PerfectWalk : public ::testing::TestWithParam<Scenario> {};

TEST_P(PerfectWalk, ReachesThePreGraspPose) {
  Trial run;
  run.scenario = GetParam();
  const Outcome out = Simulate(run);
  EXPECT_TRUE(out.status.Reached()) << out.status.reason;
  EXPECT_LT(out.ErrorCm(), 1.0);
  EXPECT_LT(std::abs(WrapAngle(out.final_pose.theta - out.true_pre_grasp.theta)) / kDeg, 2.0);
  EXPECT_TRUE(CheckGrasp(Room().objects[0], out.final_pose, GraspConfig{}).ok);
  ASSERT_FALSE(out.records.empty());
  EXPECT_EQ(out.records.front().index, 0);
  for (const ControlPointRecord& r : out.records) {
    // The approach cuts straight to the object-derived pose; the path bends round the crate.
    EXPECT_LT(r.distance_to_path * 100.0, r.phase == Phase::kPath ? 0.1 : 3.0) << r.index;
  }
  EXPECT_EQ(out.replans, 0);
}
INSTANTIATE_TEST_SUITE_P(Scenarios, PerfectWalk,
                         ::testing::Values(Scenario::kOpenLoop, Scenario::kPathFeedback,
                                           Scenario::kObjectApproach));

TEST(Mission, FeedbackOrdersTheFinalErrorsAsInTable1) {
  std::vector<double> errors[3];
  for (unsigned seed = 1; seed <= 10; ++seed) {
    for (int k = 0; k < 3; ++k) {
      Trial run;
      run.scenario = static_cast<Scenario>(k + 1);
      run.walk = Drifting(seed);
      run.pose_noise = 0.015;
      run.heading_noise_deg = 1.0;
      run.object_noise = 0.003;
      run.seed = seed;
      const Outcome out = Simulate(run);
      errors[k].push_back(out.ErrorCm());
      if (std::getenv("PLANEMAP_VERBOSE"))
        std::printf("seed %u scenario %d: %.1f cm, %zu records, %d replans, %s\n", seed, k + 1, out.ErrorCm(),
                    out.records.size(), out.replans, out.status.reason.c_str());
      if (k > 0) {
        EXPECT_TRUE(out.status.Reached() || out.status.reason.find("approach_steps_max") != std::string::npos)
            << out.status.reason;
      }
    }
  }
  const double s1 = Median(errors[0]), s2 = Median(errors[1]), s3 = Median(errors[2]);
  std::printf("final pre-grasp position error, median of 10 seeds [cm]: scenario 1 %.1f, 2 %.1f, 3 %.1f\n",
              s1, s2, s3);
  EXPECT_GT(s1, s2);
  EXPECT_GT(s2, s3);
  EXPECT_LT(s3, 3.0);
}

// Distance from p to the nearest obstacle of the room, and to the target box [m].
double CrateOrWallDistance(const Eigen::Vector2d& p) {
  static const Footprint crate = FootprintOf(Room().objects[1]);
  return std::min(crate.Distance(p), 3.5 - p.x());
}
double BoxDistance(const Eigen::Vector2d& p) {
  static const Footprint box = FootprintOf(Room().objects[0]);
  return box.Distance(p);
}

TEST(Mission, NeitherPathNorWalkCrossesAnInflatedObstacle) {
  const PlannerConfig planner;
  for (int k = 0; k < 3; ++k) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      Trial run;
      run.scenario = static_cast<Scenario>(k + 1);
      run.walk = Drifting(seed);
      run.pose_noise = 0.015;
      run.seed = seed;
      const Outcome out = Simulate(run);
      for (size_t i = 1; i < out.path.size(); ++i) {
        const Eigen::Vector2d a = out.path[i - 1].Position(), b = out.path[i].Position();
        for (double s = 0.0; s <= 1.0; s += 0.01) {
          const Eigen::Vector2d p = a + s * (b - a);
          const bool last_leg = (p - out.final_target.Position()).norm() <= planner.approach_distance;
          ASSERT_GE(CrateOrWallDistance(p) * 100.0, planner.robot_radius * 100.0);
          ASSERT_GE(BoxDistance(p) * 100.0,
                    (last_leg ? planner.final_leg_radius : planner.robot_radius) * 100.0);
        }
      }
      // The walk itself keeps clear: no closer than the last leg's body radius (feedback corrects
      // the gait; the open loop stops before a leg without open_loop_margin).
      for (const Pose2& pose : out.trajectory) {
        ASSERT_GE(std::min(CrateOrWallDistance(pose.Position()), BoxDistance(pose.Position())) * 100.0,
                  planner.final_leg_radius * 100.0)
            << "scenario " << k + 1 << " seed " << seed;
      }
    }
  }
}

// An obstacle mapped only after the plan (a bench's seat, seen edge-on from the start): given the
// current map, the next stop's grid holds it and the rest of the path crosses it, so the mission
// re-plans around it and the robot keeps its clearance. Without the map it walks into it.
TEST(Mission, AnObstacleMappedOnTheWayIsWalkedAround) {
  PlaneMap map = Room();
  map.objects.pop_back();  // no crate: the plan runs straight at the box
  PlaneMap later = map;
  later.objects.push_back(Box({1.0, 0.0, 0.2}, 0.0, {0.4, 1.2, 0.4}));  // a bench across the way
  const Footprint bench = FootprintOf(later.objects.back());
  const PlannerConfig planner;
  for (const bool with_map : {true, false}) {
    FakeHumanoid robot({0.0, 0.0, 0.0}, WalkError{}, 1);
    Mission mission(Scenario::kObjectApproach, MissionConfig{}, planner, GraspConfig{}, &robot);
    const PlanResult plan = mission.Plan(map, 0, {0.0, 0.0, 0.0});
    ASSERT_TRUE(plan.ok) << plan.reason;
    ASSERT_LT(DistanceToPath(plan.path, {1.0, 0.0}), 0.1);  // the first plan crosses the bench
    double nearest = std::numeric_limits<double>::infinity();
    for (int frame = 0; frame < 200 * kRate && !mission.Done(); ++frame) {
      const double t = frame / kRate;
      const PlaneMap& current = t < 2.0 ? map : later;  // seen after 2 s of walking
      mission.Update(t, robot.TruePose(), &map.objects[0], with_map ? &current : nullptr);
      robot.Advance(1.0 / kRate);
      nearest = std::min(nearest, bench.Distance(robot.TruePose().Position()));
    }
    if (with_map) {
      EXPECT_TRUE(mission.Status().Reached()) << mission.Status().reason;
      EXPECT_GE(mission.Replans(), 1);
      EXPECT_GE(nearest * 100.0, planner.robot_radius * 100.0 - 1.0);  // cm; the grid's half cell
    } else {
      EXPECT_LT(nearest * 100.0, 1.0);  // through it
    }
  }
}

// A surface first mapped after the plan right at the target (here at its pre-grasp pose) may be
// the target itself, moved: within moved_target_zone it is the target's estimate's to take, not an
// obstacle of the grid rebuilt on the way. With no zone the same surface leaves no way on.
TEST(Mission, ASurfaceNewlyMappedAtTheTargetIsNoObstacleWithinTheMovedTargetZone) {
  PlaneMap map = Room();
  map.objects.pop_back();
  for (const double zone : {MissionConfig{}.moved_target_zone, 0.0}) {
    FakeHumanoid robot({0.0, 0.0, 0.0}, WalkError{}, 1);
    MissionConfig config;
    config.moved_target_zone = zone;
    Mission mission(Scenario::kPathFeedback, config, PlannerConfig{}, GraspConfig{}, &robot);
    ASSERT_TRUE(mission.Plan(map, 0, {0.0, 0.0, 0.0}).ok);
    const Pose2 goal = mission.PreGraspTarget();
    PlaneMap later = map;
    later.landmarks.push_back(Rectangle(static_cast<int>(later.landmarks.size()), {goal.x, goal.y, 0.2}, kX, 0.05, kZ, 0.15));
    for (int frame = 0; frame < 200 * kRate && !mission.Done(); ++frame) {
      const double t = frame / kRate;
      mission.Update(t, robot.TruePose(), &map.objects[0], t < 2.0 ? &map : &later);
      robot.Advance(1.0 / kRate);
    }
    if (zone > 0.0) {
      EXPECT_TRUE(mission.Status().Reached()) << mission.Status().reason;
      EXPECT_EQ(mission.Replans(), 0);
    } else {
      EXPECT_FALSE(mission.Status().Reached());
      EXPECT_TRUE(mission.Blocked()) << mission.Status().reason;
    }
  }
}

// A blind leg cannot correct the gait's error on the way: scenario 1 refuses one that would keep
// less than open_loop_margin, and stops where the last accepted leg ended, that far clear.
TEST(Mission, TheOpenLoopStopsBeforeALegWithoutMargin) {
  const PlannerConfig planner;
  Trial run;
  run.scenario = Scenario::kOpenLoop;
  run.mission.open_loop_margin = 0.0;
  const Outcome reached = Simulate(run);
  ASSERT_TRUE(reached.status.Reached()) << reached.status.reason;
  // The perfect walk's last leg keeps less than this beyond the toes (final_leg_radius) ...
  const double box_at_end = BoxDistance(reached.final_pose.Position());
  run.mission.open_loop_margin = box_at_end - planner.final_leg_radius + 0.01;
  const Outcome out = Simulate(run);
  EXPECT_EQ(out.status.outcome, MissionStatus::Outcome::kStopped);
  EXPECT_NE(out.status.reason.find("open_loop_margin"), std::string::npos) << out.status.reason;
  EXPECT_FALSE(out.walking_at_end);
  // ... so the robot stops at an earlier control point, farther than the margin from the box.
  EXPECT_GE(BoxDistance(out.final_pose.Position()) * 100.0,
            (planner.final_leg_radius + run.mission.open_loop_margin) * 100.0);
  EXPECT_LT(out.records.size(), reached.records.size());
}

TEST(Mission, ScenarioThreeSwitchesToTheObjectAfterEightControlPointsOnceNear) {
  // The paper's rule (approach_max_distance out of the way): the object from the 8th point on.
  // With it, where the 8th point is still more than approach_max_distance from the pre-grasp
  // pose, the path goes on until the robot is that close.
  for (const double max_distance : {100.0, MissionConfig{}.approach_max_distance}) {
    Trial run;
    run.mission.approach_max_distance = max_distance;
    const Outcome out = Simulate(run);
    ASSERT_TRUE(out.status.Reached()) << out.status.reason;
    int last_path_index = -1;
    double last_time = -1.0;
    Pose2 switched;
    for (const ControlPointRecord& r : out.records) {
      if (r.phase == Phase::kPath) {
        last_path_index = r.index;
        switched = r.estimate;
      }
      EXPECT_GT(r.time, last_time);
      last_time = r.time;
    }
    const double distance = (switched.Position() - out.final_target.Position()).norm();
    if (max_distance > 10.0) {
      EXPECT_EQ(last_path_index, MissionConfig{}.path_following_points);
      EXPECT_GT(distance, MissionConfig{}.approach_max_distance);  // the case the bound is for
    } else {
      EXPECT_GT(last_path_index, MissionConfig{}.path_following_points);
      EXPECT_LE(distance, max_distance + 0.02);  // the estimate's noise
    }
    EXPECT_EQ(out.records.back().phase, Phase::kApproach);
  }
}

TEST(Mission, LosingTheEstimateStopsTheRobotTurnsOnTheSpotThenGivesUpWithAReason) {
  Trial run;
  run.scenario = Scenario::kPathFeedback;
  run.lost_from = 4.0;
  run.lost_to = 1e9;
  const Outcome out = Simulate(run);
  const MissionConfig config;
  EXPECT_EQ(out.status.outcome, MissionStatus::Outcome::kStopped);
  EXPECT_NE(out.status.reason.find("no pose estimate for"), std::string::npos) << out.status.reason;
  EXPECT_NE(out.status.reason.find("after turning on the spot 8 times"), std::string::npos) << out.status.reason;
  EXPECT_FALSE(out.walking_at_end);
  // Standing from lost_timeout (and a frame) after the last estimate on: it only turns there.
  const size_t still = static_cast<size_t>(std::ceil((run.lost_from + config.lost_timeout) * kRate)) + 2;
  ASSERT_LT(still, out.trajectory.size());
  const Eigen::Vector2d parked = out.trajectory[still].Position();
  double turned = 0.0;
  for (size_t f = still; f < out.trajectory.size(); ++f) {
    ASSERT_EQ(out.trajectory[f].Position(), parked) << f;
    turned += WrapAngle(out.trajectory[f].theta - out.trajectory[f - 1].theta);
  }
  // recovery_turns_max turns of recovery_turn_deg: a whole turn.
  EXPECT_NEAR(turned / kDeg, config.recovery_turns_max * config.recovery_turn_deg, 1.0);
  EXPECT_GE(static_cast<double>(out.trajectory.size()) / kRate, run.lost_from + config.give_up_timeout);
}

// A drifting walker with 1 cm of estimate noise that loses its estimate at 4 s; reaches the
// pre-grasp pose within 3 cm.
Outcome LostAtFourSeconds(double lost_to, double lost_until_turned_deg) {
  Trial run;
  run.walk = Drifting(3);
  run.pose_noise = 0.01;
  run.lost_from = 4.0;
  run.lost_to = lost_to;
  run.lost_until_turned_deg = lost_until_turned_deg;
  const Outcome out = Simulate(run);
  EXPECT_TRUE(out.status.Reached()) << out.status.reason;
  EXPECT_LT(out.ErrorCm(), 3.0);
  return out;
}

TEST(Mission, ARobotLostWhereNothingMappedIsInViewTurnsUntilItIsAndWalksOn) {
  // No estimate from 4 s on until the robot has turned 80 deg: what it faced then fixed no pose.
  const Outcome out = LostAtFourSeconds(1e9, 80.0);
  // Two recovery turns (90 deg) brought it back; then it turned back to its way.
  const size_t lost = static_cast<size_t>(4.0 * kRate);
  double most = 0.0;
  for (size_t f = lost; f < out.trajectory.size(); ++f)
    most = std::max(most, std::abs(WrapAngle(out.trajectory[f].theta - out.trajectory[lost].theta)));
  EXPECT_GT(most / kDeg, 80.0);
}

TEST(Mission, AShortLossOnlyPausesTheWalk) {
  const Outcome out = LostAtFourSeconds(6.0, 0.0);
  const size_t from = static_cast<size_t>(4.6 * kRate), to = static_cast<size_t>(6.0 * kRate) - 1;
  EXPECT_EQ(out.trajectory[from].Position(), out.trajectory[to].Position());
}

TEST(Mission, AMovedObjectIsRetargeted) {
  for (Scenario scenario : {Scenario::kPathFeedback, Scenario::kObjectApproach}) {
    Trial run;
    run.scenario = scenario;
    run.walk = Drifting(4);
    run.pose_noise = 0.01;
    run.object_noise = 0.003;
    run.object_moves_at = 3.0;
    run.object_shift = {0.1, 0.3};
    const Outcome out = Simulate(run);
    EXPECT_TRUE(out.status.Reached()) << out.status.reason;
    EXPECT_GE(out.replans, 1);
    EXPECT_GT((out.planned_pre_grasp.Position() - out.true_pre_grasp.Position()).norm(), 0.25);
    EXPECT_LT((out.final_target.Position() - out.true_pre_grasp.Position()).norm() * 100.0, 3.0);
    EXPECT_LT(out.ErrorCm(), scenario == Scenario::kObjectApproach ? 2.0 : 5.0) << static_cast<int>(scenario);
    ASSERT_FALSE(out.records.empty());
    EXPECT_GE(out.records.back().plan, 1);
  }
}

// The caller learns on the way that the target is not the one wanted (nav::RuledOut): the mission
// ends at once, the robot stands where it was, and it may choose again (Blocked). A mission not
// running takes no notice.
TEST(Mission, GivingUpStopsTheRobotAndLetsTheCallerChooseAgain) {
  const PlaneMap map = Room();
  FakeHumanoid robot({0.0, 0.0, 0.0}, WalkError{}, 1);
  Mission mission(Scenario::kObjectApproach, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot);
  mission.GiveUp("before any plan");
  EXPECT_FALSE(mission.Done());
  EXPECT_FALSE(mission.Blocked());
  ASSERT_TRUE(mission.Plan(map, 0, {0.0, 0.0, 0.0}).ok);
  double t = 0.0;
  for (; t < 3.0; t += 1.0 / kRate) {
    mission.Update(t, robot.TruePose(), &map.objects[0]);
    robot.Advance(1.0 / kRate);
  }
  ASSERT_TRUE(robot.IsWalking());
  ASSERT_FALSE(mission.Done());
  const Eigen::Vector2d there = robot.TruePose().Position();
  mission.GiveUp("object 0 proved not the target on the way: 4 x 32 x 41 cm");
  EXPECT_TRUE(mission.Done());
  EXPECT_TRUE(mission.Blocked());
  EXPECT_FALSE(mission.Status().Reached());
  EXPECT_EQ(mission.Status().reason, "object 0 proved not the target on the way: 4 x 32 x 41 cm");
  EXPECT_FALSE(robot.IsWalking());
  for (; t < 5.0; t += 1.0 / kRate) {
    mission.Update(t, robot.TruePose(), &map.objects[0]);
    robot.Advance(1.0 / kRate);
  }
  EXPECT_LT(100.0 * (robot.TruePose().Position() - there).norm(), 0.1) << "cm";
}

TEST(Mission, PlanFailuresComeBackWithReasons) {
  FakeHumanoid robot({}, {}, 1);
  Mission mission(Scenario::kObjectApproach, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot);
  mission.Update(0.0, Pose2{}, nullptr);  // before a plan: nothing happens
  EXPECT_FALSE(robot.IsWalking());
  EXPECT_FALSE(mission.Done());
  PlaneMap map = Room();
  PlanResult plan = mission.Plan(map, 7, {});
  EXPECT_FALSE(plan.ok);
  EXPECT_NE(plan.reason.find("object 7 is not in the map (2 objects)"), std::string::npos) << plan.reason;
  map.objects[0].dimensions.y() = 0.6;
  plan = mission.Plan(map, 0, {});
  EXPECT_FALSE(plan.ok);
  EXPECT_NE(plan.reason.find("cannot be grasped"), std::string::npos) << plan.reason;
  map = Room();
  plan = mission.Plan(map, 0, {0.9, 0.0, 0.0});  // standing on the crate
  EXPECT_FALSE(plan.ok);
  EXPECT_NE(plan.reason.find("start (0.90, 0.00) is blocked"), std::string::npos) << plan.reason;
  MissionConfig bad;
  bad.settle_time = -1.0;
  EXPECT_THROW(Mission(Scenario::kOpenLoop, bad, PlannerConfig{}, GraspConfig{}, &robot),
               std::invalid_argument);
  // The last leg may not keep more from the box than the pre-grasp pose does.
  PlannerConfig wide;
  wide.final_leg_radius = GraspConfig{}.body_clearance;
  EXPECT_THROW(Mission(Scenario::kOpenLoop, MissionConfig{}, wide, GraspConfig{}, &robot), std::invalid_argument);
}

// Floor and wall as Room()'s; no object mapped, but one face of a box 2.5 m ahead (seen
// square-on: one face, no object); a short face of an object classified a chair (`decided`:
// with its height measured); a short face seen once; a locker's tall door.
PlaneMap SearchRoom(bool decided) {
  PlaneMap map;
  map.landmarks.push_back(Rectangle(0, {1.25, 0.0, 0.0}, kX, 2.25, kY, 2.0));
  map.landmarks[0].floor_votes = 1;
  map.landmarks.push_back(Rectangle(1, {3.5, 0.0, 1.0}, kZ, 1.0, kY, 2.0));
  map.landmarks.push_back(Rectangle(2, {2.5, 0.3, 0.13}, kY, 0.16, kZ, 0.13));
  map.landmarks.push_back(Rectangle(3, {1.5, -1.0, 0.2}, kX, 0.15, kZ, 0.2));
  map.landmarks.push_back(Rectangle(4, {1.2, 1.0, 0.15}, kX, 0.15, kZ, 0.15));
  map.landmarks.push_back(Rectangle(5, {3.0, -1.5, 0.9}, kX, 0.25, kZ, 0.9));
  map.landmarks.push_back(Rectangle(6, {2.0, 0.8, 0.215}, kY, 0.02, kZ, 0.215));  // a chair leg, 4 cm wide
  for (PlaneLandmark& l : map.landmarks) l.observations = 10;
  map.landmarks[4].observations = 1;
  MapObject chair = Box({1.5, -1.15, 0.2}, 0.0, {0.3, 0.3, 0.4});
  chair.label = "chair";
  chair.landmarks = {3};
  chair.dimension_complete[2] = decided;
  map.objects.push_back(chair);
  return map;
}

TEST(Search, CandidatesAreLowNarrowFacesNoMeasuredObjectExplains) {
  const SearchConfig config;
  std::vector<SearchCandidate> c = SearchCandidates(SearchRoom(true), Pose2{}, config, TargetDescription{});
  ASSERT_EQ(c.size(), 1u);  // not the floor, the wall, the chair's face, the face seen once, the door, the leg
  EXPECT_EQ(c[0].landmark, 2);
  EXPECT_LT(100.0 * (c[0].center - Eigen::Vector2d(2.5, 0.3)).norm(), 1.0);
  EXPECT_LT(std::acos(c[0].normal.dot(-Eigen::Vector2d::UnitX())) / kDeg, 1.0);
  EXPECT_NEAR(c[0].distance, std::hypot(2.5, 0.3), 0.01);
  // With its height unmeasured the "chair" may be a box whose top went unseen: nearer, first.
  c = SearchCandidates(SearchRoom(false), Pose2{}, config, TargetDescription{});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].landmark, 3);
  EXPECT_EQ(c[1].landmark, 2);
  // A "box" measured at 30 x 30 x 40 cm where the task asks for a 20 x 15 x 25 cm one (a crate
  // before the parcel): its face is no candidate; the 32 cm wide face no object explains still is.
  PlaneMap crate = SearchRoom(true);
  crate.objects[0].label = "box";
  const TargetDescription parcel{"box", Eigen::Vector3d(0.20, 0.15, 0.25), 0.05};
  c = SearchCandidates(crate, Pose2{}, config, parcel);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].landmark, 2);
  EXPECT_EQ(SearchCandidates(crate, Pose2{}, config, TargetDescription{}).size(), 2u) << "any size";
}

TEST(Search, WalksToAViewpointOffTheFaceThenLooksNowhereTwice) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const PlaneMap map = SearchRoom(true);
    FakeHumanoid robot({}, Drifting(seed), seed);
    SearchConfig config;
    config.turns_max = 0;  // with no view left it would turn on the spot (WithNoViewToWalkToItTurnsOnTheSpot)
    Search search(config, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot);
    std::string why;
    ASSERT_TRUE(search.Next(map, Pose2{}, TargetDescription{}, &why)) << why;
    ASSERT_EQ(search.Viewpoints().size(), 1u);
    const Viewpoint v = search.Viewpoints()[0];
    const Eigen::Vector2d off = v.pose.Position() - v.candidate.center;
    EXPECT_NEAR(off.norm(), config.view_distance, 1e-9);
    EXPECT_NEAR(std::acos(off.normalized().dot(v.candidate.normal)) / kDeg, config.view_angle_deg, 1e-6);
    EXPECT_NEAR(WrapAngle(v.pose.theta - std::atan2(-off.y(), -off.x())), 0.0, 1e-9);  // facing the face
    EXPECT_LT(v.pose.y, v.candidate.center.y());  // of the two sides, the one nearer the robot
    for (int frame = 0; frame < 120 * kRate && search.Walking(); ++frame) {
      search.Update(frame / kRate, robot.TruePose());  // an exact estimate: the gait drifts
      robot.Advance(1.0 / kRate);
    }
    ASSERT_TRUE(search.Status().Reached()) << search.Status().reason;
    EXPECT_NE(search.Status().reason.find("the viewpoint"), std::string::npos) << search.Status().reason;
    EXPECT_LT(100.0 * (robot.TruePose().Position() - v.pose.Position()).norm(), 3.0);
    EXPECT_LT(std::abs(WrapAngle(robot.TruePose().theta - v.pose.theta)) / kDeg, 3.0);
    EXPECT_FALSE(search.Next(map, robot.TruePose(), TargetDescription{}, &why));
    EXPECT_NE(why.find("every candidate face was looked at again (1 viewpoints)"), std::string::npos) << why;
  }
  FakeHumanoid robot({}, {}, 1);
  SearchConfig none;  // no face to look at, no exploring, no turning: nothing left
  none.views_max = 0;
  none.explore = false;
  none.turns_max = 0;
  std::string why;
  EXPECT_FALSE(Search(none, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot)
                   .Next(SearchRoom(true), Pose2{}, TargetDescription{}, &why));
  EXPECT_NE(why.find("search.views_max"), std::string::npos) << why;
  PlaneMap bare = SearchRoom(true);  // floor and wall only
  bare.landmarks.resize(2);
  bare.objects.clear();
  SearchConfig no_turns;
  no_turns.turns_max = 0;
  EXPECT_FALSE(Search(no_turns, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot)
                   .Next(bare, Pose2{}, TargetDescription{}, &why));
  EXPECT_NE(why.find("no face in the map could be the target's"), std::string::npos) << why;
  SearchConfig bad;
  bad.view_distance = 0.0;
  EXPECT_THROW(Search(bad, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot), std::invalid_argument);
  // Settings that are each valid but contradict one another are named too.
  auto message = [&robot](const SearchConfig& c) {
    try {
      Search(c, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  SearchConfig ranges;
  ranges.explore_min_range = 3.5;  // beyond explore_max_range (3.0)
  EXPECT_NE(message(ranges).find("search.explore_min_range (3.5) must be below search.explore_max_range (3)"),
            std::string::npos)
      << message(ranges);
  SearchConfig widths;
  widths.candidate_min_width = 0.7;  // beyond candidate_max_width (0.6)
  EXPECT_NE(message(widths).find("search.candidate_min_width"), std::string::npos) << message(widths);
  SearchConfig fov;
  fov.explore_fov_deg = 270.0;
  EXPECT_NE(message(fov).find("search.explore_fov_deg"), std::string::npos) << message(fov);
}

// A viewpoint that an obstacle seen on the way turns out to stand in (a table's leg, a bench) is
// given up: the walk stops short with a pose estimate, not lost, and the search may go on.
TEST(Search, AViewpointFoundBlockedOnTheWayIsGivenUp) {
  const PlaneMap map = SearchRoom(true);
  FakeHumanoid robot({}, {}, 1);
  SearchConfig config;
  config.turns_max = 0;
  Search search(config, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot);
  std::string why;
  ASSERT_TRUE(search.Next(map, Pose2{}, TargetDescription{}, &why)) << why;
  const Eigen::Vector2d view = search.Viewpoints()[0].pose.Position();
  PlaneMap later = map;
  later.objects.push_back(Box({view.x(), view.y(), 0.2}, 0.0, {0.3, 0.3, 0.4}));  // where it would stand
  int frame = 0;
  for (; frame < 120 * kRate && search.Walking(); ++frame) {
    const double t = frame / kRate;
    search.Update(t, robot.TruePose(), t < 1.0 ? &map : &later);
    robot.Advance(1.0 / kRate);
  }
  EXPECT_FALSE(search.Status().Reached());
  EXPECT_TRUE(search.GaveUpView()) << search.Status().reason;
  EXPECT_NE(search.Status().reason.find("blocked"), std::string::npos) << search.Status().reason;
  EXPECT_GT(100.0 * (robot.TruePose().Position() - view).norm(), 20.0);  // it stopped short of it, cm
  // A walk that ends lost is no view given up.
  FakeHumanoid lost_robot({}, {}, 1);
  Search lost(config, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &lost_robot);
  ASSERT_TRUE(lost.Next(map, Pose2{}, TargetDescription{}, &why)) << why;
  for (frame = 0; frame < 120 * kRate && lost.Walking(); ++frame) {
    const double t = frame / kRate;
    lost.Update(t, t < 1.0 ? std::optional<Pose2>(lost_robot.TruePose()) : std::nullopt, &map);
    lost_robot.Advance(1.0 / kRate);
  }
  EXPECT_FALSE(lost.Status().Reached());
  EXPECT_FALSE(lost.GaveUpView()) << lost.Status().reason;
}

// A room whose floor the map holds but for the shadow of a 1 m shelf 1.2 m ahead of the start:
// the wedge behind it as seen from the origin.
bool InShadow(const Eigen::Vector2d& p) { return p.x() > 1.3 && std::abs(p.y()) < 0.4 * p.x() / 1.2; }

PlaneMap ShadowRoom() {
  PlaneMap map;
  PlaneLandmark floor = Rectangle(0, {2.0, 0.0, 0.0}, kX, 2.5, kY, 2.0);
  floor.points.erase(std::remove_if(floor.points.begin(), floor.points.end(),
                                    [](const Eigen::Vector3f& p) { return InShadow(p.head<2>().cast<double>()); }),
                     floor.points.end());
  floor.floor_votes = 1;
  map.landmarks.push_back(floor);
  map.landmarks.push_back(Rectangle(1, {1.2, 0.0, 0.5}, kY, 0.4, kZ, 0.5));  // the shelf's front
  for (PlaneLandmark& l : map.landmarks) l.observations = 10;
  return map;
}

TEST(Search, WithNoCandidateFaceItWalksToWhereTheUnseenFloorComesIntoView) {
  const SearchConfig config;
  const PlaneMap map = ShadowRoom();
  double wedge = 0.0;  // the unseen area, on the explore grid's cells [m^2]
  for (double x = -0.5; x < 4.5; x += config.explore_cell) {
    for (double y = -2.0; y < 2.0; y += config.explore_cell) wedge += InShadow({x, y}) ? config.explore_cell * config.explore_cell : 0.0;
  }
  const std::vector<ExploreView> views = ExploreViews(map, Pose2{}, config, PlannerConfig{});
  ASSERT_FALSE(views.empty());
  const ExploreView& best = views.front();
  std::printf("unseen floor %.2f m^2; best view at (%.2f, %.2f) m heading %.0f deg takes in %.2f m^2; %zu views\n", wedge,
              best.pose.x, best.pose.y, best.pose.theta / kDeg, best.unseen_area, views.size());
  EXPECT_GE(best.unseen_area, 1.0);            // m^2: it sees behind the shelf
  EXPECT_LE(best.unseen_area, wedge + 1e-9);   // no more than there is
  EXPECT_LE(best.pose.Position().norm(), config.explore_max_walk);
  // Beside the shelf, not behind its front: the shadow's middle is in its field of view, in range.
  const Eigen::Vector2d middle(2.8, 0.0), to = middle - best.pose.Position();
  EXPECT_LT(std::abs(WrapAngle(std::atan2(to.y(), to.x()) - best.pose.theta)) / kDeg, config.explore_fov_deg / 2.0 + 15.0);
  EXPECT_LT(to.norm(), config.explore_max_range);
  EXPECT_GT(std::abs(best.pose.y), 0.4 + PlannerConfig{}.robot_radius);  // walked past the shelf's side

  // Search::Next walks there when no face is a candidate; with the whole floor seen, nowhere.
  FakeHumanoid robot({}, {}, 1);
  Search search(config, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot);
  std::string why;
  ASSERT_TRUE(search.Next(map, Pose2{}, TargetDescription{}, &why)) << why;
  ASSERT_EQ(search.Viewpoints().size(), 1u);
  EXPECT_TRUE(search.Viewpoints()[0].Explores());
  EXPECT_NEAR(search.Viewpoints()[0].unseen_area, best.unseen_area, 1e-9);
  // A box face glimpsed in the shadow: its viewpoints (0.7 m off, 40 deg) stand on floor not seen
  // yet, which the planner would take as free: the robot explores instead.
  PlaneMap glimpsed = map;
  glimpsed.landmarks.push_back(Rectangle(2, {2.5, 0.0, 0.13}, kY, 0.15, kZ, 0.13));
  glimpsed.landmarks.back().observations = 10;
  ASSERT_EQ(SearchCandidates(glimpsed, Pose2{}, config, TargetDescription{}).size(), 1u);
  Search again(config, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot);
  ASSERT_TRUE(again.Next(glimpsed, Pose2{}, TargetDescription{}, &why)) << why;
  EXPECT_TRUE(again.Viewpoints()[0].Explores());
  PlaneMap seen = map;
  seen.landmarks[0] = Rectangle(0, {2.0, 0.0, 0.0}, kX, 2.5, kY, 2.0);
  seen.landmarks[0].floor_votes = 1;
  EXPECT_TRUE(ExploreViews(seen, Pose2{}, config, PlannerConfig{}).empty());
  SearchConfig no_turns = config;
  no_turns.turns_max = 0;
  EXPECT_FALSE(Search(no_turns, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot).Next(seen, Pose2{}, TargetDescription{}, &why));
  EXPECT_NE(why.find("of floor not seen yet into view"), std::string::npos) << why;
  SearchConfig faces_only = no_turns;
  faces_only.explore = false;
  EXPECT_FALSE(Search(faces_only, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot).Next(map, Pose2{}, TargetDescription{}, &why));
  EXPECT_NE(why.find("no face in the map could be the target's"), std::string::npos) << why;
}

// A robot 0.6 m in front of a 1 m shelf 0.8 m wide (the atelier's start): the shelf's front fills
// the view, the map holds no floor, so there is no face to look at and nowhere to explore. It
// turns on the spot, turn_step_deg at a time, without walking, until turns_max.
TEST(Search, WithNoViewToWalkToItTurnsOnTheSpot) {
  PlaneMap map;
  map.landmarks.push_back(Rectangle(0, {0.61, 0.0, 0.5}, kY, 0.4, kZ, 0.5));
  map.landmarks[0].observations = 10;
  const SearchConfig config;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    FakeHumanoid robot({}, Drifting(seed), seed);
    Search search(config, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot);
    std::string why;
    double time = 0.0, commanded = 0.0;
    for (int turn = 1; turn <= config.turns_max; ++turn) {
      ASSERT_TRUE(search.Next(map, robot.TruePose(), TargetDescription{}, &why)) << why;
      ASSERT_EQ(search.Viewpoints().size(), static_cast<size_t>(turn));
      const Viewpoint& v = search.Viewpoints().back();
      EXPECT_TRUE(v.turn);
      EXPECT_FALSE(v.Explores());
      commanded += config.turn_step_deg;
      EXPECT_TRUE(search.Walking());
      for (int frame = 0; frame < 20 * kRate && search.Walking(); ++frame, time += 1.0 / kRate) {
        search.Update(time, robot.TruePose());
        robot.Advance(1.0 / kRate);
      }
      ASSERT_FALSE(search.Walking());
      ASSERT_TRUE(search.Status().Reached()) << search.Status().reason;
      // Turned on the spot: heading within the gait's error (noise_turn 2%) of the command.
      EXPECT_LT(std::abs(WrapAngle(robot.TruePose().theta - commanded * kDeg)) / kDeg, 0.05 * commanded) << turn;
      EXPECT_LT(100.0 * robot.TruePose().Position().norm(), 1.0);  // cm: no walk
    }
    EXPECT_FALSE(search.Next(map, robot.TruePose(), TargetDescription{}, &why));
    EXPECT_NE(why.find("turned on the spot 7 times (search.turns_max)"), std::string::npos) << why;
    EXPECT_NE(why.find("no face in the map could be the target's"), std::string::npos) << why;
  }
  SearchConfig bad;
  bad.turn_step_deg = 0.0;
  FakeHumanoid robot({}, {}, 1);
  EXPECT_THROW(Search(bad, MissionConfig{}, PlannerConfig{}, GraspConfig{}, &robot), std::invalid_argument);
}

TEST(Mission, DistanceToPath) {
  const std::vector<Pose2> path{{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {1.0, 1.0, 0.0}};
  EXPECT_NEAR(DistanceToPath(path, {0.5, 0.2}), 0.2, 1e-12);
  EXPECT_NEAR(DistanceToPath(path, {1.3, 0.5}), 0.3, 1e-12);
  EXPECT_NEAR(DistanceToPath(path, {-0.3, -0.4}), 0.5, 1e-12);
  EXPECT_TRUE(std::isinf(DistanceToPath({}, {0.0, 0.0})));
}

}  // namespace
}  // namespace planemap::nav
