// The closed loop of `planemap approach` on the default scene, and one run in each room added
// after tuning: rendered frames, the product's perception and estimation, the simulated
// humanoid. A small set of seeds; the full table is `planemap approach --table --seeds 20`
// (docs/approach.md). Frames at 15 Hz to keep the suite short.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include "planemap/apps/approach.h"
#include "planemap/sim/scene.h"
#include "test_support.h"

namespace planemap {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

ApproachOptions Options(int scenario, int seed) {
  ApproachOptions o;
  o.scene = testing::SourcePath("configs/scenes/default.yaml");
  o.camera = testing::SourcePath("configs/cameras/xtion_nao.yaml");
  o.config = testing::SourcePath("configs/default.yaml");
  o.patterns = testing::SourcePath("configs/patterns.yaml");
  o.scenario = scenario;
  o.seed = seed;
  o.rate = 15.0;
  return o;
}

void Print(const char* what, const ApproachRun& r) {
  std::printf("%s: scenario %d seed %d: %s (%s); average error %.1f cm, pre-grasp %.1f cm %.1f deg, grasp %s, collision %s\n", what,
              r.scenario, r.seed, r.Reached() ? "reached" : "stopped", r.status.reason.c_str(), 100 * r.average_error,
              100 * r.position_error, r.heading_error * kRadToDeg, r.grasp_ok ? "ok" : r.grasp_reason.c_str(),
              r.collided ? r.collision.c_str() : "none");
}

// Scenario 3 with `seed` in configs/scenes/<name>.yaml, printed.
ApproachRun RunInScene(const std::string& name, int seed) {
  ApproachOptions o = Options(3, seed);
  o.scene = testing::SourcePath("configs/scenes/" + name + ".yaml");
  const ApproachRun r = RunApproachOnce(o);
  Print(name.c_str(), r);
  return r;
}

// Reached the pre-grasp pose of the scene's box within 3 cm and 5 deg, the grasp check passing,
// no collision.
void ExpectAtThePreGraspPose(const ApproachRun& r) {
  ASSERT_TRUE(r.Reached()) << r.status.reason;
  EXPECT_EQ(r.target, "box");
  EXPECT_FALSE(r.collided) << r.collision;
  EXPECT_LT(r.position_error * 100.0, 3.0) << "cm";
  EXPECT_LT(r.heading_error * kRadToDeg, 5.0) << "deg";
  EXPECT_TRUE(r.grasp_ok) << r.grasp_reason;
}

TEST(Approach, FeedbackBeatsOpenLoopAndScenarioThreeEndsAtThePreGraspPose) {
  const ApproachRun open = RunApproachOnce(Options(1, 3));
  const ApproachRun path = RunApproachOnce(Options(2, 3));
  const ApproachRun object = RunApproachOnce(Options(3, 3));
  Print("open loop", open);
  Print("path feedback", path);
  Print("object approach", object);
  for (const ApproachRun* r : {&open, &path, &object}) {
    ASSERT_TRUE(r->planned) << r->status.reason;
    EXPECT_FALSE(r->collided) << r->collision;
    EXPECT_GE(r->stops.size(), 8u) << "control points";
  }
  EXPECT_GT(open.position_error, path.position_error) << "m";
  EXPECT_GT(open.position_error, object.position_error) << "m";
  EXPECT_GT(open.average_error, path.average_error) << "m";
  EXPECT_TRUE(object.Reached()) << object.status.reason;
  EXPECT_LT(object.position_error, 0.03) << "m";
  EXPECT_LT(object.heading_error * kRadToDeg, 5.0) << "deg";
  EXPECT_TRUE(object.grasp_ok) << object.grasp_reason;
  // The estimate the controllers used and the truth agree at every control point to a few cm.
  for (const ApproachStop& s : object.stops) EXPECT_NEAR(s.record.distance_to_path, s.truth_to_path, 0.03) << "m, stop " << s.record.index;
}

TEST(Approach, ASecondWithoutFramesStillEndsAtThePreGraspPose) {
  ApproachOptions o = Options(3, 2);
  o.drop_at = 12.0;  // walking along the path
  o.drop_duration = 1.0;
  const ApproachRun r = RunApproachOnce(o);
  Print("frames dropped", r);
  EXPECT_GE(r.lost_frames, 14);
  ASSERT_TRUE(r.Reached()) << r.status.reason;
  EXPECT_LT(r.position_error, 0.03) << "m";
  EXPECT_TRUE(r.grasp_ok) << r.grasp_reason;
  EXPECT_FALSE(r.collided) << r.collision;
}

TEST(Approach, AnObjectMovedAndTurnedAfterThePlanIsApproachedWhereItIsNow) {
  ApproachOptions o = Options(3, 4);
  o.move_object_at = 8.0;  // walking along the path
  o.move_object_by = {0.10, 0.08, 15.0};  // slid 12.8 cm and turned 15 deg
  const ApproachRun r = RunApproachOnce(o);
  Print("object moved", r);
  EXPECT_FALSE(r.collided) << r.collision;
  ASSERT_TRUE(r.Reached()) << r.status.reason;
  // Scored against the moved box: the map's box restarted from the views that saw it moved, and
  // the mission re-planned to it.
  EXPECT_GE(r.stops.size(), 2u);
  EXPECT_GE(r.stops.back().record.plan, 1) << "re-plans";
  EXPECT_LT(r.position_error, 0.03) << "m from the moved box's pre-grasp pose";
  EXPECT_LT(r.heading_error * kRadToDeg, 5.0) << "deg";
  EXPECT_TRUE(r.grasp_ok) << r.grasp_reason;
}

// The two rooms added after the navigation was tuned (configs/scenes/lab.yaml, hall.yaml; the
// full tables: docs/approach.md).
TEST(Approach, ScenarioThreeEndsAtThePreGraspPoseInRoomsAddedAfterTuning) {
  for (const char* scene : {"configs/scenes/lab.yaml", "configs/scenes/hall.yaml"}) {
    ApproachOptions o = Options(3, 1);
    o.scene = testing::SourcePath(scene);
    const ApproachRun r = RunApproachOnce(o);
    Print(scene, r);
    ASSERT_TRUE(r.Reached()) << scene << ": " << r.status.reason;
    EXPECT_FALSE(r.collided) << scene << ": " << r.collision;
    EXPECT_LT(r.position_error, 0.03) << scene << ": m";
    EXPECT_LT(r.heading_error * kRadToDeg, 5.0) << scene << ": deg";
    EXPECT_TRUE(r.grasp_ok) << scene << ": " << r.grasp_reason;
  }
}

// The corridor's box stands 3 m ahead, nearly square-on: from the start it shows one face and a
// glancing top, never three faces. The robot looks again from a viewpoint off that face.
TEST(Approach, ABoxNotMappedFromTheStartIsLookedAtAgainThenApproached) {
  const ApproachRun r = RunInScene("corridor", 1);
  ASSERT_FALSE(r.viewpoints.empty());
  for (const nav::Viewpoint& v : r.viewpoints) {
    std::printf("  viewpoint (%.2f, %.2f) m, %.2f m from the face at (%.2f, %.2f) m\n", v.pose.x, v.pose.y,
                (v.pose.Position() - v.candidate.center).norm(), v.candidate.center.x(),
                v.candidate.center.y());
  }
  ExpectAtThePreGraspPose(r);
}

// Garage seed 9 (configs/scenes/garage.yaml): a far wall strip and a locker face, each mapped
// once 4 deg off, agreed with a pose 13 cm off the truth; the tracker took it in one frame,
// kept it for the whole object approach, and the robot walked into the box. Landmarks not yet
// confirmed by 3 views weigh less in RANSAC, and with odometry a pose far from its prediction
// needs more support.
TEST(Approach, PlanesMappedOnceDoNotPullThePoseOff) {
  const ApproachRun r = RunInScene("garage", 9);
  ASSERT_FALSE(r.pose_errors.empty());
  const double worst = *std::max_element(r.pose_errors.begin(), r.pose_errors.end());
  std::printf("  base position estimate over %zu frames: worst %.1f cm\n", r.pose_errors.size(), 100 * worst);
  // The pull was 14.6 cm. The tracker's own worst on this walk is a few cm and depends on the way
  // walked: 3.6 cm since scenario 3 follows the path until 0.6 m from the pre-grasp pose
  // (mission.approach_max_distance), at a stop on the path; median 0.5 cm.
  EXPECT_LT(worst * 100.0, 5.0) << "cm (was 14.6)";
  ExpectAtThePreGraspPose(r);  // (was 12.9 cm off, in the box)
}

// The hideout (configs/scenes/hideout.yaml, the tuning scene of the exploring search): a 1 m
// shelf stands between the start and the box, so no face in view can be the box's. The robot
// walks to where the floor behind the shelf comes into view, then looks again and approaches.
TEST(Approach, ABoxHiddenBehindAShelfIsFoundByExploring) {
  const ApproachRun r = RunInScene("hideout", 1);
  ASSERT_FALSE(r.viewpoints.empty());
  EXPECT_TRUE(r.viewpoints.front().Explores());
  EXPECT_GE(r.viewpoints.front().unseen_area, 1.0) << "m^2";
  ExpectAtThePreGraspPose(r);
}

// The atelier (configs/scenes/atelier.yaml, measured once as an unseen room in which every run
// waited 240 s for a pose; since then a tuning scene): the robot starts 0.6 m in front of a 1 m
// shelf that fills its view, so the map holds one plane and no floor, no face to look at and no
// floor to explore. It turns on the spot, maps the floor, explores round the shelf and approaches.
TEST(Approach, ARobotFacingATallShelfTurnsOnTheSpotThenFindsTheBox) {
  const ApproachRun r = RunInScene("atelier", 1);
  ASSERT_FALSE(r.viewpoints.empty());
  EXPECT_TRUE(r.viewpoints.front().turn);
  EXPECT_EQ(r.lost_frames, 0);
  ExpectAtThePreGraspPose(r);
}

// The gallery (configs/scenes/gallery.yaml, measured once as an unseen room in which 9 of 20 runs
// approached the wrong object; since then a tuning scene): a 32 x 28 x 40 cm crate, a graspable
// box to the frontend, stands before the 24 x 21 x 33 cm box and hides it from the start. The
// scene's task tells the robot the box's size; the crate, once measured, is another object, and
// its faces are no candidates to look at again. Seed 1 approached the crate before.
TEST(Approach, ACrateBeforeTheBoxIsNotTakenForItWhenTheTaskGivesItsSize) {
  const ApproachRun r = RunInScene("gallery", 1);
  EXPECT_EQ(r.intended, "box");
  ExpectAtThePreGraspPose(r);
}

// The collision check holds the robot's true footprint against the parts that reach below its
// height. The pantry's table (configs/scenes/pantry.yaml) has its top 0.725 m above the floor, on
// 4 cm legs: a 0.58 m humanoid walks under the top (every pantry run did, to the box beyond it)
// but not through a leg. The table's bounding box counted every such run as a collision.
TEST(Approach, ARobotUnderATablesTopCollidesOnlyWithItsLegs) {
  const sim::Scene scene = sim::LoadScene(testing::SourcePath("configs/scenes/pantry.yaml"));
  const ApproachOptions options;
  const sim::SceneObject& table = scene.object("table");
  const Eigen::Vector2d centre = table.T_world_object.translation().head<2>();
  const Eigen::Vector2d leg = (table.T_world_object * Eigen::Vector3d(0.41, 0.26, 0.0)).head<2>();
  // Distance from p to the nearest footprint of the named object [m].
  auto distance = [](const std::vector<std::pair<std::string, nav::Footprint>>& footprints, const Eigen::Vector2d& p,
                     const std::string& object) {
    double best = 1e9;
    for (const auto& [name, f] : footprints) {
      if (name == object) best = std::min(best, f.Distance(p));
    }
    return best;
  };
  const auto footprints = CollisionFootprints(scene, options.body_height);
  // Under the top's centre: 0.458 m from the nearest leg's footprint (legs 4 cm thick, their
  // centres 0.41 x 0.26 m from the top's).
  EXPECT_NEAR(distance(footprints, centre, "table"), std::hypot(0.39, 0.24), 1e-6) << "m";
  EXPECT_EQ(distance(footprints, leg, "table"), 0.0) << "m, at a leg";
  // The box and the locker stand on the floor: their whole footprints count.
  EXPECT_EQ(distance(footprints, scene.object("box").T_world_object.translation().head<2>(), "box"), 0.0);
  EXPECT_EQ(distance(footprints, scene.object("locker").T_world_object.translation().head<2>(), "locker"), 0.0);
  // A robot taller than the top's underside hits the top anywhere under it.
  EXPECT_EQ(distance(CollisionFootprints(scene, 0.80), centre, "table"), 0.0) << "m";
}

TEST(Approach, BadOptionsAreNamed) {
  ApproachOptions o = Options(4, 1);
  EXPECT_THROW(RunApproachOnce(o), std::exception);
  o = Options(3, 1);
  o.scene = "/nonexistent/scene.yaml";
  EXPECT_THROW(RunApproachOnce(o), std::exception);
}

// A table loads its files once: a settings file edited (here: broken) while it runs neither
// stops nor changes the runs still to come; a fresh load names the broken file.
TEST(Approach, ATablesInputsAreLoadedOnce) {
  ApproachOptions o = Options(3, 1);
  const std::string copy = ::testing::TempDir() + "planemap_approach_settings.yaml";
  {
    std::ifstream in(o.config);
    std::ofstream out(copy);
    out << in.rdbuf();
  }
  o.config = copy;
  o.max_time = 1.0;
  const std::shared_ptr<const ApproachInputs> inputs = LoadApproachInputs(o);
  std::ofstream(copy) << "mission:\n  k_position: -1.0\n";
  const ApproachRun r = RunApproachOnce(o, *inputs);
  EXPECT_GE(r.frames, 14);  // 1 s at 15 Hz
  try {
    RunApproachOnce(o);
    ADD_FAILURE() << "a broken settings file was read without an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find(copy), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("k_position"), std::string::npos) << e.what();
  }
  std::remove(copy.c_str());
}

}  // namespace
}  // namespace planemap
