// Poses from plane correspondences found without a prediction (plane_relocalization.h): a
// furnished room seen from a camera turned and moved far from where it was, exact planes and
// noisy ones; nothing from too little structure.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "planemap/frontend/plane_relocalization.h"
#include "test_support.h"

namespace planemap {
namespace {

using testing::RotationErrorDeg;
using testing::TranslationError;

constexpr double kRadPerDeg = M_PI / 180.0;

// A world plane through `point` with unit normal `normal` (pointing into the room) and a patch of
// `size` (axis-aligned box around the point).
RelocalizationPlane WorldPlane(const Eigen::Vector3d& normal, const Eigen::Vector3d& point, const Eigen::Vector3d& size,
                               double weight = 1.0) {
  RelocalizationPlane p;
  p.plane = {normal.normalized(), -normal.normalized().dot(point)};
  p.centroid = point;
  p.extent = {point - 0.5 * size, point + 0.5 * size};
  p.weight = weight;
  return p;
}

// A 5 x 4 m room: floor, three walls, a table top, a box's top and two sides, a shelf board.
std::vector<RelocalizationPlane> Room() {
  return {WorldPlane({0, 0, 1}, {2.5, 2.0, 0.0}, {5.0, 4.0, 0.02}, 3.0),
          WorldPlane({1, 0, 0}, {0.0, 2.0, 1.2}, {0.02, 4.0, 2.4}, 2.0),
          WorldPlane({0, -1, 0}, {2.5, 4.0, 1.2}, {5.0, 0.02, 2.4}, 2.0),
          WorldPlane({0, 1, 0}, {2.5, 0.0, 1.2}, {5.0, 0.02, 2.4}, 2.0),
          WorldPlane({0, 0, 1}, {1.0, 3.0, 0.75}, {1.2, 0.8, 0.02}),
          WorldPlane({0, 0, 1}, {3.0, 1.5, 0.30}, {0.4, 0.3, 0.02}),
          WorldPlane({-1, 0, 0}, {2.8, 1.5, 0.15}, {0.02, 0.3, 0.3}),
          WorldPlane({0, 1, 0}, {3.0, 1.35, 0.15}, {0.4, 0.02, 0.3}),
          WorldPlane({0, 0, 1}, {0.2, 1.0, 1.40}, {0.4, 1.0, 0.02})};
}

// The planes as a camera at T_world_camera sees them (camera frame), optionally perturbed: normals
// turned by up to `angle_deg`, offsets moved by up to `offset`.
std::vector<RelocalizationPlane> Seen(const std::vector<RelocalizationPlane>& world, const Pose3& T_world_camera,
                                      double angle_deg = 0.0, double offset = 0.0, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Pose3 T_camera_world = T_world_camera.inverse();
  std::vector<RelocalizationPlane> seen;
  for (const RelocalizationPlane& w : world) {
    RelocalizationPlane c;
    const Eigen::Vector3d axis = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    const Eigen::Matrix3d tilt = Eigen::AngleAxisd(angle_deg * kRadPerDeg * unit(rng), axis).toRotationMatrix();
    c.centroid = T_camera_world * w.centroid;
    const Eigen::Vector3d n = tilt * (T_camera_world.linear() * w.plane.normal);
    c.plane = {n, -n.dot(c.centroid) + offset * unit(rng)};
    c.extent = TransformBox(T_camera_world, w.extent.low, w.extent.high);
    c.weight = w.weight;
    seen.push_back(c);
  }
  return seen;
}

const Pose3 kFarAway = MakePoseRpy(0.3, -0.2, 1.2, Eigen::Vector3d(1.2, 0.8, 1.1));  // 70 deg, 1.8 m from the identity

TEST(Relocalization, ExactPlanesGiveTheExactPoseFarFromAnyPrediction) {
  const std::vector<RelocalizationPlane> room = Room();
  const std::vector<RelocalizationHypothesis> poses = RelocalizeByPlanes(Seen(room, kFarAway), room, RelocalizationConfig{});
  ASSERT_FALSE(poses.empty());
  EXPECT_LT(TranslationError(poses.front().T_target_source, kFarAway), 1e-6) << "m";
  EXPECT_LT(RotationErrorDeg(poses.front().T_target_source, kFarAway), 1e-6) << "deg";
  EXPECT_EQ(poses.front().planes, static_cast<int>(room.size()));
}

TEST(Relocalization, NoisyPlanesGiveAPoseWithinTheirNoise) {
  // Normals off by up to 1 deg and offsets by up to 1 cm, as a real sensor's planes a few metres away.
  const std::vector<RelocalizationPlane> room = Room();
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const std::vector<RelocalizationHypothesis> poses =
        RelocalizeByPlanes(Seen(room, kFarAway, 1.0, 0.01, seed), room, RelocalizationConfig{});
    ASSERT_FALSE(poses.empty()) << "seed " << seed;
    EXPECT_LT(TranslationError(poses.front().T_target_source, kFarAway), 0.05) << "m, seed " << seed;
    EXPECT_LT(RotationErrorDeg(poses.front().T_target_source, kFarAway), 2.0) << "deg, seed " << seed;
  }
}

TEST(Relocalization, TwoDirectionsFixNoPose) {
  // The floor, the table top and one wall: the translation along the wall is free.
  const std::vector<RelocalizationPlane> room = Room();
  const std::vector<RelocalizationPlane> few = {room[0], room[4], room[1]};
  EXPECT_TRUE(RelocalizeByPlanes(Seen(few, kFarAway), room, RelocalizationConfig{}).empty());
}

TEST(Relocalization, SameSeedSameHypotheses) {
  const std::vector<RelocalizationPlane> room = Room();
  const std::vector<RelocalizationPlane> seen = Seen(room, kFarAway, 1.0, 0.01, 3);
  const std::vector<RelocalizationHypothesis> a = RelocalizeByPlanes(seen, room, RelocalizationConfig{});
  const std::vector<RelocalizationHypothesis> b = RelocalizeByPlanes(seen, room, RelocalizationConfig{});
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) EXPECT_TRUE(a[k].T_target_source.isApprox(b[k].T_target_source, 0.0));
}

}  // namespace
}  // namespace planemap
