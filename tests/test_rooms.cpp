// planemap rooms: the room generator (every room within its ranges and reachable, the same rooms
// for the same seed), the reach check, and the command's resumable CSV.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "planemap/apps/app_config.h"
#include "planemap/apps/commands.h"
#include "planemap/apps/rooms.h"
#include "planemap/core/config.h"
#include "planemap/core/error.h"
#include "planemap/sim/scene.h"
#include "test_support.h"

namespace planemap {
namespace {

using planemap::testing::SourcePath;
using planemap::testing::TempDir;

constexpr double kBodyHeight = 0.58;  // ApproachOptions::body_height [m]

// The footprint of an object (its bounding box) seen from above.
nav::Footprint Footprint(const sim::SceneObject& o) {
  const Eigen::Matrix3d r = o.T_world_object.linear();
  nav::Footprint f;
  f.center = o.Center().head<2>();
  f.axes.col(0) = r.col(0).head<2>().normalized();
  f.axes.col(1) = r.col(1).head<2>().normalized();
  f.half_size = 0.5 * o.dimensions.head<2>();
  return f;
}

// Whether the segment a-b passes through the footprint (sampled every 5 mm).
bool Crosses(const nav::Footprint& f, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const int n = static_cast<int>((b - a).norm() / 0.005) + 1;
  for (int k = 0; k <= n; ++k) {
    if (f.Distance(a + (b - a) * k / n) == 0.0) return true;
  }
  return false;
}

TEST(RoomGenerator, TheDefaultFileEqualsTheDefaultsInCode) {
  const RoomGeneratorConfig loaded = LoadConfigFile<RoomGeneratorConfig>(SourcePath("configs/rooms/default.yaml"));
  EXPECT_EQ(YAML::Dump(ConfigToYaml(loaded)), YAML::Dump(ConfigToYaml(RoomGeneratorConfig{})));
}

TEST(RoomGenerator, TheSameSeedGivesTheSameRoomAndAnotherIndexAnother) {
  const RoomGeneratorConfig config;
  const AppConfig app;
  const GeneratedRoom a = GenerateRoom(config, 7, 3, app.planner, app.grasp, kBodyHeight);
  const GeneratedRoom b = GenerateRoom(config, 7, 3, app.planner, app.grasp, kBodyHeight);
  const GeneratedRoom c = GenerateRoom(config, 7, 4, app.planner, app.grasp, kBodyHeight);
  const GeneratedRoom d = GenerateRoom(config, 8, 3, app.planner, app.grasp, kBodyHeight);
  EXPECT_EQ(YAML::Dump(a.scene), YAML::Dump(b.scene));
  EXPECT_NE(YAML::Dump(a.scene), YAML::Dump(c.scene));
  EXPECT_NE(YAML::Dump(a.scene), YAML::Dump(d.scene));
}

// Every room of a 40-room sequence is within the generator's ranges, its things apart and inside
// the walls, its box graspable and reachable; across the rooms the box stands free, by walls and
// in corners, and in some rooms another thing stands on the line from the start to the box.
TEST(RoomGenerator, EveryRoomIsWithinItsRangesAndItsBoxReachable) {
  const RoomGeneratorConfig config;
  const AppConfig app;
  std::map<std::string, int> placements;
  int hidden = 0;
  for (int k = 1; k <= 40; ++k) {
    const GeneratedRoom room = GenerateRoom(config, 1, k, app.planner, app.grasp, kBodyHeight);
    SCOPED_TRACE("room " + std::to_string(k) + ": " + room.summary);
    const sim::Scene scene = sim::ParseScene(room.scene, "room");
    ASSERT_EQ(scene.task_object, "box");
    const YAML::Node floor = room.scene["floor"];
    const Eigen::Vector2d size(floor["size"][0].as<double>(), floor["size"][1].as<double>());
    const Eigen::Vector2d centre(floor["center"][0].as<double>(), floor["center"][1].as<double>());
    EXPECT_GE(size.minCoeff(), config.room_size_min - 1e-3);
    EXPECT_LE(size.maxCoeff(), config.room_size_max + 1e-3);
    const Eigen::Vector2d low = centre - 0.5 * size, high = centre + 0.5 * size;
    // The start (the origin) inside, away from the walls.
    EXPECT_GE(std::min((-low).minCoeff(), high.minCoeff()), config.start_wall_margin - 1e-3);

    const sim::SceneObject& box = scene.object("box");
    const double narrow = std::min(box.dimensions.x(), box.dimensions.y());
    EXPECT_GE(narrow, config.box_narrow_min - 1e-3);
    EXPECT_LE(narrow, config.box_narrow_max + 1e-3);
    EXPECT_GE(box.dimensions.z(), config.box_height_min - 1e-3);
    EXPECT_LE(box.dimensions.z(), config.box_height_max + 1e-3);
    EXPECT_NEAR(box.Center().z(), 0.5 * box.dimensions.z(), 1e-3);  // on the floor
    // Graspable with the approach's own error: some side the hands span has a band that wide
    // (checked before the scene file rounds sizes and positions to millimetres: 1 mm less here).
    MapObject truth;
    truth.center = box.Center();
    truth.axes = box.T_world_object.linear();
    truth.dimensions = box.dimensions;
    double widest = -1.0;
    for (const Eigen::Vector2d& side : nav::GraspSides(truth, app.grasp, -truth.center.head<2>())) {
      widest = std::max(widest, nav::GraspBand(truth, nav::GraspFaces(truth, side), app.grasp).Width());
    }
    EXPECT_GE(100.0 * widest, 100.0 * config.box_min_band - 0.1);
    const double distance = box.Center().head<2>().norm();
    EXPECT_GE(distance, config.box_distance_min - 1e-3);
    EXPECT_LE(distance, config.box_distance_max + 1e-3);

    const int others = static_cast<int>(scene.objects.size()) - 1;
    EXPECT_GE(others, config.others_min);
    EXPECT_LE(others, config.others_max);
    for (const sim::SceneObject& o : scene.objects) {
      const nav::Footprint f = Footprint(o);
      for (double su : {-1.0, 1.0}) {
        for (double sv : {-1.0, 1.0}) {
          const Eigen::Vector2d corner = f.center + f.axes * Eigen::Vector2d(su * f.half_size.x(), sv * f.half_size.y());
          EXPECT_TRUE((corner.array() >= low.array() - 1e-3).all() && (corner.array() <= high.array() + 1e-3).all())
              << o.name << " pokes through a wall";
        }
      }
      if (o.name == "box") continue;
      EXPECT_GE(f.Distance(Eigen::Vector2d::Zero()), config.start_clearance - 0.01) << o.name << " stands on the start";
      // Apart from the box: the box's corners keep the gap from the other's footprint.
      const nav::Footprint b = Footprint(box);
      for (double su : {-1.0, 1.0}) {
        for (double sv : {-1.0, 1.0}) {
          const Eigen::Vector2d corner = b.center + b.axes * Eigen::Vector2d(su * b.half_size.x(), sv * b.half_size.y());
          EXPECT_GE(f.Distance(corner), config.object_gap - 0.01) << o.name << " crowds the box";
        }
      }
      if (Crosses(f, Eigen::Vector2d::Zero(), box.Center().head<2>())) ++hidden;
    }
    // The reach check, again on the parsed scene: a path from the start to a pre-grasp pose.
    const RoomReach reach = CheckRoomReach(scene, {0, 0, 0}, app.planner, app.grasp, kBodyHeight);
    EXPECT_TRUE(reach.ok) << reach.reason;
    EXPECT_GE(reach.path_length, distance - 0.5);  // the pre-grasp pose stands at most ~0.5 m off the centre
    for (const char* where : {"free-standing", "by a wall", "in a corner"}) {
      if (room.summary.find(where) != std::string::npos) ++placements[where];
    }
  }
  EXPECT_GE(placements["free-standing"], 5);
  EXPECT_GE(placements["by a wall"], 5);
  EXPECT_GE(placements["in a corner"], 2);
  EXPECT_GE(hidden, 8);  // about half the rooms put a thing on the way; some of it on the very line
}

// A box behind a bench that spans the room wall to wall: no pre-grasp pose can be reached.
TEST(RoomReachCheck, ABoxBehindAWallToWallBenchCannotBeReached) {
  const char* const kScene = R"(
name: closed
task: {object: box}
floor: {center: [1.5, 0.0], size: [5.0, 3.0]}
walls:
  - {name: s, from: [-1.0, -1.5], to: [4.0, -1.5], height: 2.5}
  - {name: e, from: [4.0, -1.5], to: [4.0, 1.5], height: 2.5}
  - {name: n, from: [4.0, 1.5], to: [-1.0, 1.5], height: 2.5}
  - {name: w, from: [-1.0, 1.5], to: [-1.0, -1.5], height: 2.5}
objects:
  - {name: box, type: box, position: [3.0, 0.0, 0.15], rpy_deg: [0, 0, 0], dimensions: [0.3, 0.3, 0.3]}
  - name: bench
    type: furniture
    position: [2.0, 0.0, 0.0]
    rpy_deg: [0, 0, 0]
    parts:
      - {name: seat, position: [0.0, 0.0, 0.42], dimensions: [0.4, 3.0, 0.04]}
)";
  const AppConfig app;
  const sim::Scene closed = sim::ParseScene(YAML::Load(kScene), "closed");
  const RoomReach reach = CheckRoomReach(closed, {0, 0, 0}, app.planner, app.grasp, kBodyHeight);
  EXPECT_FALSE(reach.ok);
  EXPECT_NE(reach.reason.find("no path"), std::string::npos) << reach.reason;

  // The same bench 1 m shorter leaves a way round it: reachable, the path longer than straight.
  YAML::Node open = YAML::Load(kScene);
  open["objects"][1]["position"][1] = 0.5;
  open["objects"][1]["parts"][0]["dimensions"][1] = 2.0;
  const RoomReach around = CheckRoomReach(sim::ParseScene(open, "open"), {0, 0, 0}, app.planner, app.grasp, kBodyHeight);
  ASSERT_TRUE(around.ok) << around.reason;
  EXPECT_GT(around.path_length, 2.6);  // the straight way to the near face's pre-grasp pose is about 2.6 m
}

TEST(RoomGenerator, RangesThatContradictEachOtherAreNamed) {
  RoomGeneratorConfig config;
  config.box_height_min = 0.6;
  const AppConfig app;
  try {
    GenerateRoom(config, 1, 1, app.planner, app.grasp, kBodyHeight);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("box_height_min above box_height_max"), std::string::npos) << e.what();
  }
}

std::string ReadFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// One short run in one generated room: a row per run in runs.csv, a summary; the same command
// again runs nothing and leaves the CSV as it was; other settings in the same folder are refused.
TEST(RoomsCommand, WritesARowPerRunAndResumesWithoutRunningAgain) {
  TempDir dir;
  RoomsOptions options;
  options.count = 1;
  options.room_seed = 3;
  options.run.rate = 10.0;
  options.run.max_time = 6.0;  // short: the CSV and the summary, not the approach, are under test
  options.threads = 1;
  options.out = (std::filesystem::path(dir.path()) / "rooms").string();
  options.generator = SourcePath("configs/rooms/default.yaml");
  options.run.config = SourcePath("configs/default.yaml");
  options.run.camera = SourcePath("configs/cameras/xtion_nao.yaml");
  options.run.patterns = SourcePath("configs/patterns.yaml");
  ASSERT_EQ(RunRooms(options), 0);
  const std::filesystem::path csv = std::filesystem::path(dir.path()) / "rooms" / "runs.csv";
  const std::string first = ReadFile(csv);
  std::istringstream lines(first);
  std::string header, row, extra;
  std::getline(lines, header);
  ASSERT_TRUE(std::getline(lines, row));
  EXPECT_FALSE(std::getline(lines, extra));
  EXPECT_EQ(header.substr(0, 24), "room,scene,seed,scenario");
  EXPECT_EQ(row.substr(0, 2), "1,");
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(dir.path()) / "rooms" / "rooms" / "room_001.yaml"));
  const std::string summary = ReadFile(std::filesystem::path(dir.path()) / "rooms" / "summary.txt");
  EXPECT_NE(summary.find("of 1 ("), std::string::npos) << summary;

  ASSERT_EQ(RunRooms(options), 0);  // resumed: nothing to run
  EXPECT_EQ(ReadFile(csv), first);

  options.run.scenario = 2;
  EXPECT_THROW(RunRooms(options), InputError);
}

}  // namespace
}  // namespace planemap
