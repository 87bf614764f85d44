// The simulated walk: where the head camera goes, how fast, and how it sways.
#include <cmath>

#include <gtest/gtest.h>

#include "planemap/sim/walk.h"
#include "test_support.h"

namespace planemap::sim {
namespace {

using planemap::testing::SourcePath;
using planemap::testing::ThrowsWith;

constexpr double kRadToDeg = 180.0 / M_PI;

// Pitch of the optical axis below the horizon [deg].
double PitchDownDeg(const Pose3& T_world_camera) {
  return std::asin(-T_world_camera.linear().col(2).z()) * kRadToDeg;
}

TEST(Walk, StraightWalkWithoutSwayHasExactGeometry) {
  WalkConfig c;
  c.waypoints = {0.0, 0.0, 3.0, 0.0};
  c.sway_lateral = c.sway_vertical = c.sway_roll_deg = c.sway_yaw_deg = 0.0;
  const Trajectory walk = GenerateWalk(c);
  // 3 m at 0.1 m/s plus 0.5 s standing at each end, at 30 Hz.
  EXPECT_EQ(walk.size(), static_cast<size_t>(std::floor((30.0 + 1.0) * 30.0)) + 1);
  EXPECT_NEAR(walk[1].stamp - walk[0].stamp, 1.0 / 30.0, 1e-12);
  for (const StampedPose& p : walk) {
    EXPECT_NEAR(p.T_world_camera.translation().z(), 0.52, 1e-12);
    EXPECT_NEAR(p.T_world_camera.translation().y(), 0.0, 1e-12);
    EXPECT_NEAR(PitchDownDeg(p.T_world_camera), 20.0, 1e-9);
  }
  EXPECT_NEAR(walk.back().T_world_camera.translation().x(), 3.0, 1e-9);
  // Mid-walk: 15 s after leaving, 1.5 m along.
  EXPECT_NEAR(walk[static_cast<size_t>(15.5 * 30)].T_world_camera.translation().x(), 1.5, 1e-9);
}

TEST(Walk, HeadSwaysAtTheStepFrequencyWithTheConfiguredAmplitude) {
  WalkConfig c;
  c.waypoints = {0.0, 0.0, 3.0, 0.0};
  const Trajectory walk = GenerateWalk(c);
  double max_lateral = 0.0, max_vertical = 0.0;
  int sign_changes = 0;
  double previous = 0.0;
  for (const StampedPose& p : walk) {
    const double y = p.T_world_camera.translation().y();
    max_lateral = std::max(max_lateral, std::abs(y));
    max_vertical = std::max(max_vertical, p.T_world_camera.translation().z() - c.camera_height);
    if (previous != 0.0 && y * previous < 0.0) ++sign_changes;
    if (y != 0.0) previous = y;
  }
  EXPECT_NEAR(max_lateral, c.sway_lateral, 0.001);
  EXPECT_NEAR(max_vertical, c.sway_vertical, 0.0005);
  // Sideways sway crosses the path once per step: 2 steps/s over 30 s.
  EXPECT_NEAR(sign_changes, 60, 2);
}

TEST(Walk, TurnsOnTheSpotAtCornersAndEndsAtTheLastWaypoint) {
  WalkConfig c;
  c.waypoints = {0.0, 0.0, 1.0, 0.0, 1.0, 1.0};
  c.sway_lateral = c.sway_vertical = c.sway_roll_deg = c.sway_yaw_deg = 0.0;
  const Trajectory walk = GenerateWalk(c);
  const Pose3& last = walk.back().T_world_camera;
  EXPECT_NEAR(last.translation().x(), 1.0, 1e-9);
  EXPECT_NEAR(last.translation().y(), 1.0, 1e-9);
  // Facing +y at the end: the optical axis points along world +y (tilted down).
  const Eigen::Vector3d forward = last.linear().col(2);
  EXPECT_NEAR(std::atan2(forward.y(), forward.x()) * kRadToDeg, 90.0, 1e-9);
  // 2 m walking + 90 deg at 30 deg/s + 1 s standing.
  EXPECT_NEAR(walk.back().stamp - walk.front().stamp, 20.0 + 3.0 + 1.0, 1.0 / 30.0);
}

TEST(Walk, DefaultWalkApproachesTheBox) {
  const Trajectory walk = LoadTrajectory(SourcePath("configs/walks/default.yaml"));
  const Eigen::Vector3d box(2.1, 0.1, 0.125);
  const double start = (walk.front().T_world_camera.translation() - box).head<2>().norm();
  const double end = (walk.back().T_world_camera.translation() - box).head<2>().norm();
  EXPECT_NEAR(start, 2.1, 0.01);
  EXPECT_NEAR(end, 0.55, 0.01);
}

TEST(Walk, BadWaypointsAreRejected) {
  WalkConfig c;
  c.waypoints = {0.0, 0.0, 1.0};
  EXPECT_TRUE(ThrowsWith([&] { GenerateWalk(c); }, {"waypoints"}));
  c.waypoints = {1.0, 1.0, 1.0, 1.0};
  EXPECT_TRUE(ThrowsWith([&] { GenerateWalk(c); }, {"do not leave the start point"}));
  c.waypoints = {0.0, 0.0, 1.0, 0.0};
  c.speed = -0.1;
  EXPECT_TRUE(ThrowsWith([&] { GenerateWalk(c); }, {"walk.speed", "must be > 0"}));
  // From a file, the error names it.
  planemap::testing::TempDir dir;
  const std::string one_point = dir.Write("one.yaml", "waypoints: [0, 0]\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadTrajectory(one_point); }, {one_point, "at least two points"}));
  const std::string standing = dir.Write("standing.yaml", "waypoints: [1, 1, 1, 1]\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadTrajectory(standing); }, {standing, "do not leave the start point"}));
  // A rate that is a typo: every pose would be made (and held) before the first frame. 1e12 Hz
  // also overflowed the frame count to a negative int ("no poses").
  for (const std::string rate : {"1e+08", "1e+12"}) {
    const std::string fast = dir.Write("fast.yaml", "waypoints: [0, 0, 1.5, 0]\nrate: " + rate + "\n");
    EXPECT_TRUE(ThrowsWith([&] { LoadTrajectory(fast); }, {fast, "poses (16 s at walk.rate " + rate + " Hz): more than 1e+06"}));
  }
  const std::string quick = dir.Write("quick.yaml", "waypoints: [0, 0, 1.5, 0]\nrate: 1000\n");
  EXPECT_EQ(LoadTrajectory(quick).size(), 16001u);  // 1 s held + 15 s walked + ... at 1 kHz: still fine
}

}  // namespace
}  // namespace planemap::sim
