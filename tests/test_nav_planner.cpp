// The planner: occupancy grid from a plane map, A* with shortcuts, the target's last-leg
// exemption, control points. Distances in cm against the known geometry of synthetic rooms.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/nav/planner.h"
#include "test_support.h"

namespace planemap::nav {
namespace {

using planemap::testing::Rectangle;
constexpr double kDeg = M_PI / 180.0;
const Eigen::Vector3d kX = Eigen::Vector3d::UnitX(), kY = Eigen::Vector3d::UnitY(),
                      kZ = Eigen::Vector3d::UnitZ();

// A 4 m x 3 m room: floor x in [-0.5, 3.5], y in [-1.5, 1.5]; nothing on it.
PlaneMap EmptyRoom() {
  PlaneMap map;
  map.landmarks.push_back(Rectangle(0, {1.5, 0.0, 0.0}, kX, 2.0, kY, 1.5));
  map.landmarks[0].floor_votes = 1;
  return map;
}

// Grasped from its -x face, toward a robot coming from -x.
MapObject Box(const Eigen::Vector3d& center, double yaw_deg, const Eigen::Vector3d& dimensions) {
  return planemap::testing::BoxObject(center, yaw_deg, dimensions, -1.0);
}

// Samples of a path every centimetre.
std::vector<Eigen::Vector2d> Samples(const std::vector<Pose2>& path) {
  std::vector<Eigen::Vector2d> out;
  for (size_t k = 1; k < path.size(); ++k) {
    const Eigen::Vector2d a = path[k - 1].Position(), b = path[k].Position();
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / 0.01)));
    for (int s = 0; s <= n; ++s) out.push_back(a + (b - a) * (double(s) / n));
  }
  return out;
}

TEST(Planner, StraightPathInAnEmptyRoom) {
  const PlannerConfig config;
  const OccupancyGrid grid = BuildOccupancyGrid(EmptyRoom(), config);
  ASSERT_FALSE(grid.Empty());
  const PlanResult plan = PlanPath(grid, {0.0, 0.0, 0.0}, {3.0, 0.0, 0.0});
  ASSERT_TRUE(plan.ok) << plan.reason;
  EXPECT_NEAR(plan.length * 100.0, 300.0, 0.1);
  for (const Eigen::Vector2d& p : Samples(plan.path)) EXPECT_NEAR(p.y() * 100.0, 0.0, 0.1);
  EXPECT_NEAR(plan.path.back().x, 3.0, 1e-12);
}

TEST(Planner, UnknownSpaceOutsideTheFloorIsBlocked) {
  const OccupancyGrid grid = BuildOccupancyGrid(EmptyRoom(), PlannerConfig{});
  EXPECT_TRUE(grid.Free({1.5, 0.0}));
  EXPECT_FALSE(grid.Free({3.45, 0.0}));  // 5 cm from the floor's edge: within the robot's radius
  EXPECT_FALSE(grid.Free({5.0, 0.0}));   // off the grid
  EXPECT_NEAR(grid.Clearance({3.0, 0.0}) * 100.0, 50.0, 3.0);
}

TEST(Planner, PathAroundABoxKeepsTheRobotRadius) {
  PlaneMap map = EmptyRoom();
  map.objects.push_back(Box({1.5, 0.0, 0.2}, 30.0, {0.4, 0.4, 0.4}));
  const PlannerConfig config;
  const OccupancyGrid grid = BuildOccupancyGrid(map, config);
  const PlanResult plan = PlanPath(grid, {0.0, 0.0, 0.0}, {3.0, 0.0, 0.0});
  ASSERT_TRUE(plan.ok) << plan.reason;
  const Footprint box = FootprintOf(map.objects[0]);
  double least = 1e9;
  for (const Eigen::Vector2d& p : Samples(plan.path)) least = std::min(least, box.Distance(p));
  EXPECT_GE(least * 100.0, config.robot_radius * 100.0);
  EXPECT_LE(least * 100.0, (config.robot_radius + config.clearance_margin) * 100.0 + 5.0);  // no wide detour
  EXPECT_GT(plan.length, 3.05);
  EXPECT_LT(plan.length, 3.6);
}

// A robot that stands 8 cm from a box (it needs 12) steps straight out of its clearance first,
// never nearer the box than it stands, then walks on; one standing inside the box cannot.
TEST(Planner, AStartInsideTheClearanceStepsOutFirst) {
  PlaneMap map = EmptyRoom();
  map.objects.push_back(Box({1.0, 0.0, 0.2}, 0.0, {0.4, 0.4, 0.4}));  // x in [0.8, 1.2]
  const PlannerConfig config;
  const OccupancyGrid grid = BuildOccupancyGrid(map, config);
  const Footprint box = FootprintOf(map.objects[0]);
  const Pose2 start{0.72, 0.0, 0.0};  // 8 cm from the box's -x face
  ASSERT_FALSE(grid.Free(start.Position()));
  const PlanResult plan = PlanPath(grid, start, {2.5, 0.0, 0.0});
  ASSERT_TRUE(plan.ok) << plan.reason;
  ASSERT_GE(plan.path.size(), 3u);
  const Eigen::Vector2d out = plan.path[1].Position();
  EXPECT_TRUE(grid.Free(out));
  EXPECT_LE(100.0 * (out - start.Position()).norm(), 100.0 * (config.robot_radius + config.clearance_margin) + 0.1);
  EXPECT_GE(100.0 * box.Distance(out), 100.0 * config.robot_radius - 2.0);  // the grid's cells: within 2 cm
  // The step comes no nearer the box than the start; after it, the path keeps the radius.
  const double at_start = box.Distance(start.Position());
  const std::vector<Eigen::Vector2d> step = Samples({plan.path[0], plan.path[1]});
  for (const Eigen::Vector2d& p : step) EXPECT_GE(100.0 * box.Distance(p), 100.0 * at_start - 0.5);
  std::vector<Pose2> rest(plan.path.begin() + 1, plan.path.end());
  for (const Eigen::Vector2d& p : Samples(rest)) EXPECT_GE(100.0 * box.Distance(p), 100.0 * config.robot_radius - 2.0);

  const PlanResult inside = PlanPath(grid, {1.0, 0.0, 0.0}, {2.5, 0.0, 0.0});
  EXPECT_FALSE(inside.ok);
  EXPECT_NE(inside.reason.find("no step out of it"), std::string::npos) << inside.reason;
}

// A robot standing where the map holds an obstacle (a phantom landmark's points, a drifted one's):
// its body stands there, so the grid clears standing_radius around it, and it steps out.
TEST(Planner, WhereTheRobotStandsIsNoObstacle) {
  PlaneMap map = EmptyRoom();
  map.objects.push_back(Box({1.0, 0.05, 0.2}, 0.0, {0.1, 0.1, 0.4}));  // a 10 cm post where the robot stands
  const PlannerConfig config;
  const Eigen::Vector2d standing(1.0, 0.0);
  EXPECT_EQ(BuildOccupancyGrid(map, config).Clearance(standing), 0.0);
  const OccupancyGrid grid = BuildOccupancyGrid(map, config, {}, standing);
  // The grid's clearance is a lower bound, by a cell's diagonal and the cell the edge falls in.
  EXPECT_GE(grid.Clearance(standing), config.standing_radius - (1.0 + M_SQRT2) * config.resolution);
  const PlanResult plan = PlanPath(grid, {standing.x(), standing.y(), 0.0}, {2.5, 0.0, 0.0});
  ASSERT_TRUE(plan.ok) << plan.reason;
  EXPECT_NEAR(plan.path.back().x, 2.5, 1e-12);
}

TEST(Planner, WallPointsInTheHeightBandAreObstacles) {
  PlaneMap map = EmptyRoom();
  // A wall from y = -1.5 to 0.6 at x = 1.5, 1 m high: only its landmark points mark it.
  map.landmarks.push_back(Rectangle(1, {1.5, -0.45, 0.5}, kY, 1.05, kZ, 0.5));
  // A table top at 0.8 m, above the band: no obstacle.
  map.landmarks.push_back(Rectangle(2, {2.5, 0.0, 0.8}, kX, 0.3, kY, 0.3));
  const PlannerConfig config;
  const OccupancyGrid grid = BuildOccupancyGrid(map, config);
  EXPECT_TRUE(grid.Free({2.5, 0.0}));
  const PlanResult plan = PlanPath(grid, {0.5, 0.0, 0.0}, {2.5, -0.5, 0.0});
  ASSERT_TRUE(plan.ok) << plan.reason;
  // Against what the map knows of the wall: its voxel points.
  for (const Eigen::Vector2d& p : Samples(plan.path)) {
    for (const Eigen::Vector3f& q : map.landmarks[1].points) {
      ASSERT_GE((p - q.head<2>().cast<double>()).norm() * 100.0, config.robot_radius * 100.0)
          << p.transpose();
    }
  }
  EXPECT_GT(plan.path[1].y, 0.6);  // round the wall's end
}

TEST(Planner, BlockedStartGoalOrNoPathSayWhich) {
  PlaneMap map = EmptyRoom();
  map.objects.push_back(Box({1.5, 0.0, 0.2}, 0.0, {0.4, 0.4, 0.4}));
  const OccupancyGrid grid = BuildOccupancyGrid(map, PlannerConfig{});
  PlanResult plan = PlanPath(grid, {0.0, 0.0, 0.0}, {1.6, 0.0, 0.0});
  EXPECT_FALSE(plan.ok);
  EXPECT_NE(plan.reason.find("goal (1.60, 0.00) is blocked"), std::string::npos) << plan.reason;
  plan = PlanPath(grid, {1.4, 0.1, 0.0}, {3.0, 0.0, 0.0});
  EXPECT_NE(plan.reason.find("start (1.40, 0.10) is blocked"), std::string::npos) << plan.reason;
  plan = PlanPath(grid, {0.0, 0.0, 0.0}, {6.0, 0.0, 0.0});
  EXPECT_NE(plan.reason.find("outside the map's floor"), std::string::npos) << plan.reason;
  // A wall across the whole room.
  map.landmarks.push_back(Rectangle(1, {2.0, 0.0, 0.5}, kY, 1.6, kZ, 0.5));
  plan = PlanPath(BuildOccupancyGrid(map, PlannerConfig{}), {0.0, 0.0, 0.0}, {3.0, 0.0, 0.0});
  EXPECT_FALSE(plan.ok);
  EXPECT_NE(plan.reason.find("no path"), std::string::npos) << plan.reason;
  EXPECT_NE(PlanPath(OccupancyGrid{}, {}, {}).reason.find("no floor"), std::string::npos);
}

TEST(Planner, TheTargetLetsTheLastLegIn) {
  PlaneMap map = EmptyRoom();
  map.objects.push_back(Box({2.5, 0.3, 0.125}, 20.0, {0.25, 0.35, 0.25}));
  const PlannerConfig config;
  const Eigen::Vector2d g = -map.objects[0].axes.col(0).head<2>();
  const Eigen::Vector2d stand = map.objects[0].center.head<2>() + 0.22 * g;
  const Pose2 pre_grasp{stand.x(), stand.y(), std::atan2(-g.y(), -g.x())};
  // As an ordinary obstacle the box blocks the pre-grasp pose, 9.5 cm from its face.
  EXPECT_FALSE(PlanPath(BuildOccupancyGrid(map, config), {0.0, 0.0, 0.0}, pre_grasp).ok);
  const OccupancyGrid grid = BuildOccupancyGrid(map, config, {0, pre_grasp});
  const PlanResult plan = PlanPath(grid, {0.0, -0.5, 0.0}, pre_grasp);
  ASSERT_TRUE(plan.ok) << plan.reason;
  // The last leg: straight along the grasp axis, approach_distance long.
  const Pose2& approach = plan.path[plan.path.size() - 2];
  const Eigen::Vector2d leg = plan.path.back().Position() - approach.Position();
  EXPECT_NEAR(leg.norm() * 100.0, config.approach_distance * 100.0, 0.1);
  EXPECT_NEAR(std::atan2(leg.y(), leg.x()) / kDeg, pre_grasp.theta / kDeg, 0.1);
  const Footprint box = FootprintOf(map.objects[0]);
  for (const Eigen::Vector2d& p : Samples(plan.path)) {
    const bool last_leg = (p - stand).norm() <= config.approach_distance;
    ASSERT_GE(box.Distance(p) * 100.0, (last_leg ? config.final_leg_radius : config.robot_radius) * 100.0);
  }
  EXPECT_NEAR(box.Distance(stand) * 100.0, 9.5, 0.1);
}

// A face the tracker holds twice, 3 cm in front of the box, is the box's own surface; a panel
// 8 cm in front (beyond target_margin) is an obstacle that blocks the pre-grasp pose.
TEST(Planner, TheTargetsOwnSurfacesAreNotObstacles) {
  const PlannerConfig config;
  const MapObject box = Box({2.5, 0.3, 0.125}, 0.0, {0.25, 0.35, 0.25});
  const Pose2 pre_grasp{2.5 - 0.235, 0.3, 0.0};
  for (const double gap : {0.03, 0.08}) {
    PlaneMap map = EmptyRoom();
    map.objects.push_back(box);
    map.landmarks.push_back(Rectangle(1, {2.375 - gap, 0.3, 0.125}, kY, 0.17, kZ, 0.12));
    const PlanResult plan = PlanPath(BuildOccupancyGrid(map, config, {0, pre_grasp}), {0.0, 0.0, 0.0}, pre_grasp);
    if (gap <= config.target_margin) {
      EXPECT_TRUE(plan.ok) << gap * 100 << " cm: " << plan.reason;
    } else {
      EXPECT_FALSE(plan.ok) << gap * 100 << " cm";
      EXPECT_NE(plan.reason.find("goal"), std::string::npos) << plan.reason;
    }
  }
}

TEST(Planner, ControlPointsAreEvenlySpacedAndEndAtTheGoal) {
  const std::vector<Pose2> path{{0.0, 0.0, 0.3}, {1.0, 0.0, 0.0}, {1.0, 1.0, M_PI / 2}};
  const Pose2 goal{1.0, 1.0, M_PI};
  const std::vector<Pose2> points = ControlPoints(path, 0.15, goal);
  ASSERT_EQ(points.size(), 15u);  // 2 m in 14 legs of 14.3 cm
  EXPECT_DOUBLE_EQ(points.front().theta, 0.3);
  EXPECT_DOUBLE_EQ(points.back().theta, M_PI);
  double arc = 0.0;
  for (size_t k = 1; k < points.size(); ++k) {
    const double along = std::abs(points[k].x - points[k - 1].x) + std::abs(points[k].y - points[k - 1].y);
    arc += along;
    EXPECT_NEAR(along * 100.0, 200.0 / 14.0, 1e-6) << k;  // arc length between points (L1 on this L path)
    EXPECT_LE((points[k].Position() - points[k - 1].Position()).norm(), 0.15 + 1e-9);
    if (k + 1 < points.size()) {  // along the leg ahead; at the corner, the second one
      EXPECT_NEAR(points[k].theta, points[k].x < 1.0 - 1e-9 ? 0.0 : M_PI / 2, 1e-9) << k;
    }
  }
  EXPECT_NEAR(arc, 2.0, 1e-9);
  EXPECT_EQ(ControlPoints({}, 0.15, goal).size(), 1u);
  // A spacing that is a typo: 1e-9 m asked for billions of stops (12.7 GB, then bad_alloc).
  EXPECT_TRUE(testing::ThrowsWith([&] { ControlPoints(path, 1e-9, goal); }, {"planner.control_point_spacing 1e-09 m", "control points"}));
}

TEST(Planner, SegmentFreeAndDeterminism) {
  PlaneMap map = EmptyRoom();
  map.objects.push_back(Box({1.5, 0.0, 0.2}, 0.0, {0.4, 0.4, 0.4}));
  const OccupancyGrid grid = BuildOccupancyGrid(map, PlannerConfig{});
  EXPECT_FALSE(SegmentFree(grid, {0.5, 0.0}, {2.5, 0.0}));   // through the box
  EXPECT_FALSE(SegmentFree(grid, {0.5, 0.3}, {2.5, 0.3}));   // 10 cm from it
  EXPECT_TRUE(SegmentFree(grid, {0.5, 0.38}, {2.5, 0.38}));  // 18 cm from it
  const PlanResult a = PlanPath(grid, {0.0, 0.1, 0.0}, {3.0, -0.1, 0.0});
  const PlanResult b = PlanPath(grid, {0.0, 0.1, 0.0}, {3.0, -0.1, 0.0});
  ASSERT_EQ(a.path.size(), b.path.size());
  for (size_t k = 0; k < a.path.size(); ++k) EXPECT_EQ(a.path[k].Position(), b.path[k].Position());
}

TEST(Planner, ConfigIsValidated) {
  PlannerConfig config;
  EXPECT_NO_THROW(ValidateConfig(config));
  config.resolution = 0.0;
  EXPECT_THROW(ValidateConfig(config), std::invalid_argument);
  EXPECT_TRUE(BuildOccupancyGrid(PlaneMap{}, PlannerConfig{}).Empty());  // no floor
}

}  // namespace
}  // namespace planemap::nav
