// The pre-grasp pose and the grasp check on the default scene's box (configs/scenes/default.yaml:
// centre (2.1, 0.1, 0.125) m, yaw 215 deg, depth 0.25 x width 0.35 x height 0.25 m).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/nav/grasp.h"
#include "test_support.h"

namespace planemap::nav {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The default scene's box; its +x face looks toward the start at the origin.
MapObject DefaultBox(const Eigen::Vector3d& dimensions = {0.25, 0.35, 0.25}) {
  return planemap::testing::BoxObject({2.1, 0.1, 0.125}, 215.0, dimensions, +1.0);
}

const Eigen::Vector2d kTowardStart(-1.0, 0.0);

// The default box grasped across its 35 cm from its +x face: a grasp point at standoff s is
// (s, 17.5, 12.5) cm in the base frame, its shoulder at (5, 10, 26) cm. Facing the box squarely the
// hand reaches it up to s = 5 + sqrt(26.5^2 - 7.5^2 - 13.5^2) = 26.53 cm; turned 5 deg (the band's
// heading tolerance) the far hand swings out and the limit is 25.78 cm (solved by hand, by
// bisection on the rotated points). The toes keep the base 12.5 + 9 = 21.5 cm from the centre.
constexpr double kNear = 0.215;
constexpr double kFar = 0.2578;

Pose2 AtStandoff(const MapObject& box, double standoff, double turn_deg) {
  const Eigen::Vector2d g(std::cos(215.0 * kDeg), std::sin(215.0 * kDeg));
  const Eigen::Vector2d p = box.center.head<2>() + standoff * g;
  return {p.x(), p.y(), (35.0 + turn_deg) * kDeg};
}

TEST(Grasp, TheDefaultBoxsStandoffBand) {
  const MapObject box = DefaultBox();
  GraspConfig config;
  const GraspGeometry faces = GraspFaces(box, kTowardStart);
  EXPECT_NEAR(faces.width * 100.0, 35.0, 1e-9);
  EXPECT_NEAR(faces.depth * 100.0, 25.0, 1e-9);
  const StandoffBand band = GraspBand(box, faces, config);
  EXPECT_NEAR(band.near * 100.0, kNear * 100.0, 1e-9);
  EXPECT_NEAR(band.far * 100.0, kFar * 100.0, 0.01);
  // The far end is where the grasp check, turned 5 deg, starts failing.
  for (double turn : {-5.0, 5.0}) {
    EXPECT_TRUE(CheckGrasp(box, AtStandoff(box, band.far - 1e-4, turn), config).ok);
    EXPECT_FALSE(CheckGrasp(box, AtStandoff(box, band.far + 1e-3, turn), config).ok);
  }
  EXPECT_TRUE(CheckGrasp(box, AtStandoff(box, band.far + 5e-3, 0.0), config).ok);
  config.heading_tolerance_deg = 0.0;
  const double square = 0.05 + std::sqrt(0.265 * 0.265 - 0.075 * 0.075 - 0.135 * 0.135);
  EXPECT_NEAR(GraspBand(box, faces, config).far * 100.0, square * 100.0, 1e-6);
}

TEST(Grasp, PreGraspPoseOfTheDefaultBox) {
  const MapObject box = DefaultBox();
  const GraspConfig config;
  const Eigen::Vector2d side = ChooseGraspSide(box, config, kTowardStart);
  EXPECT_NEAR(side.x(), std::cos(215.0 * kDeg), 1e-9);
  EXPECT_NEAR(side.y(), std::sin(215.0 * kDeg), 1e-9);
  const Pose2 pose = PreGraspPose(box, config, side);
  // In the band's middle out of the +x face's centre line, facing the box: heading 215 - 180 = 35 deg.
  const double standoff = 0.5 * (kNear + kFar);
  EXPECT_NEAR(pose.x, 2.1 + standoff * std::cos(215.0 * kDeg), 1e-4);
  EXPECT_NEAR(pose.y, 0.1 + standoff * std::sin(215.0 * kDeg), 1e-4);
  EXPECT_NEAR(pose.theta / kDeg, 35.0, 1e-9);
  // The near face 11.1 cm ahead of the base origin: the toes (8 cm) 3.1 cm clear.
  EXPECT_NEAR((standoff - 0.125) * 100.0, 11.14, 0.01);
  // Grasp points on the side faces, at the centre's height, left of the robot on its left.
  const GraspCheck check = CheckGrasp(box, pose, config);
  EXPECT_TRUE(check.ok) << check.reason;
  EXPECT_NEAR(check.left_point.x() * 100.0, standoff * 100.0, 0.01);
  EXPECT_NEAR(check.left_point.y() * 100.0, 17.5, 1e-6);
  EXPECT_NEAR(check.right_point.y() * 100.0, -17.5, 1e-6);
  EXPECT_NEAR(check.left_point.z() * 100.0, 12.5, 1e-6);
  EXPECT_NEAR(check.left_distance, check.right_distance, 1e-9);
  EXPECT_NEAR(check.left_distance * 100.0, 100.0 * std::hypot(standoff - 0.05, 0.075, 0.135), 0.01);
}

TEST(Grasp, OfTheSidesFacingTheRobotTheOneWithTheWidestBandIsChosen) {
  const GraspConfig config;
  const MapObject box = DefaultBox();
  // From +y the box's -y face is nearest, but the box is 35 cm deep that way: the band from the
  // toes (17.5 + 9 = 26.5 cm) to the reach (5 + sqrt(26.5^2 - 2.5^2 - 13.5^2) = 27.67 cm) is 1.2 cm
  // wide (0.4 cm turned 5 deg). Its -x face also faces +y and leaves 4.3 cm: the robot grasps from there.
  const GraspGeometry deep = GraspFaces(box, {0.0, 1.0});
  EXPECT_NEAR(deep.depth * 100.0, 35.0, 1e-9);
  EXPECT_NEAR(GraspBand(box, deep, config).Width() * 100.0, 0.4, 0.1);
  const Eigen::Vector2d side = ChooseGraspSide(box, config, {0.0, 1.0});
  EXPECT_NEAR(side.x(), std::cos(35.0 * kDeg), 1e-9);
  EXPECT_NEAR(side.y(), std::sin(35.0 * kDeg), 1e-9);
  const Pose2 pose = PreGraspPose(box, config, side);
  EXPECT_NEAR(WrapAngle(pose.theta) / kDeg, WrapAngle(215.0 * kDeg) / kDeg, 1e-9);
  EXPECT_TRUE(CheckGrasp(box, pose, config).ok) << CheckGrasp(box, pose, config).reason;
}

TEST(Grasp, WithoutAGraspableSideTheFrontendsAxisIsKeptAndTheCheckSaysWhy) {
  const GraspConfig config;
  MapObject huge = DefaultBox({0.50, 0.50, 0.25});
  const Eigen::Vector2d side = ChooseGraspSide(huge, config, {0.0, 1.0});
  EXPECT_NEAR(side.dot(huge.grasp_axis.head<2>()), 1.0, 1e-9);
  const GraspCheck check = CheckGrasp(huge, PreGraspPose(huge, config, side), config);
  EXPECT_FALSE(check.ok);
  EXPECT_NE(check.reason.find("wider than hand_span_max"), std::string::npos) << check.reason;
}

// The robot off its pre-grasp pose by `offset` [m] in its own frame, in 8 directions, turned.
class GraspNear : public ::testing::TestWithParam<double> {};

TEST_P(GraspNear, PassesWithinFewCentimetresAndFiveDegrees) {
  const MapObject box = DefaultBox();
  const GraspConfig config;
  const Pose2 pre_grasp = PreGraspPose(box, config, kTowardStart);
  for (int k = 0; k < 8; ++k) {
    for (double turn_deg : {-5.0, 0.0, 5.0}) {
      const double a = k * M_PI / 4;
      const Pose2 robot =
          Compose(pre_grasp, {GetParam() * std::cos(a), GetParam() * std::sin(a), turn_deg * kDeg});
      const GraspCheck check = CheckGrasp(box, robot, config);
      EXPECT_TRUE(check.ok) << "off " << GetParam() * 100 << " cm at " << k * 45 << " deg, turned "
                            << turn_deg << " deg: " << check.reason;
    }
  }
}
// The band is 4.3 cm deep for a robot turned 5 deg and the pose in its middle: 2 cm off either way
// holds, turned or not.
INSTANTIATE_TEST_SUITE_P(Offsets, GraspNear, ::testing::Values(0.0, 0.01, 0.02));

class GraspFar : public ::testing::TestWithParam<double> {};

TEST_P(GraspFar, FailsTenCentimetresOffOrMore) {
  const MapObject box = DefaultBox();
  const GraspConfig config;
  const Pose2 pre_grasp = PreGraspPose(box, config, kTowardStart);
  for (int k = 0; k < 8; ++k) {
    const double a = k * M_PI / 4;
    const GraspCheck check = CheckGrasp(
        box, Compose(pre_grasp, {GetParam() * std::cos(a), GetParam() * std::sin(a), 0.0}), config);
    EXPECT_FALSE(check.ok) << "off " << GetParam() * 100 << " cm at " << k * 45 << " deg";
    EXPECT_NE(check.reason.find("grasp point is"), std::string::npos) << check.reason;
  }
}
INSTANTIATE_TEST_SUITE_P(Offsets, GraspFar, ::testing::Values(0.10, 0.15, 0.30));

TEST(Grasp, FailsForAnObjectTooWideOrTooNarrow) {
  const GraspConfig config;
  MapObject wide = DefaultBox({0.25, 0.50, 0.25});
  GraspCheck check = CheckGrasp(wide, PreGraspPose(wide, config, kTowardStart), config);
  EXPECT_FALSE(check.ok);
  EXPECT_NEAR(check.width * 100.0, 50.0, 1e-9);
  EXPECT_NE(check.reason.find("50.0 cm across, wider than hand_span_max 40.0 cm"), std::string::npos)
      << check.reason;
  MapObject narrow = DefaultBox({0.25, 0.06, 0.25});
  check = CheckGrasp(narrow, PreGraspPose(narrow, config, kTowardStart), config);
  EXPECT_FALSE(check.ok);
  EXPECT_NE(check.reason.find("narrower than hand_span_min"), std::string::npos) << check.reason;
}

TEST(Grasp, TheFacesMappedPlanesPlaceTheObjectForTheHands) {
  // The map's centre 6 cm off along g and 4 cm across it (generated room 43: 6.8 cm), the +x face
  // and the side face toward -across mapped where they are; the top mapped too (no horizontal axis).
  const MapObject truth = DefaultBox();
  const GraspConfig config;
  const Eigen::Vector3d g(std::cos(215.0 * kDeg), std::sin(215.0 * kDeg), 0.0);
  const Eigen::Vector3d across(-g.y(), g.x(), 0.0), up = Eigen::Vector3d::UnitZ();
  MapObject mapped = truth;
  mapped.center += 0.06 * g + 0.04 * across;
  std::vector<PlaneLandmark> landmarks;
  landmarks.push_back(planemap::testing::Rectangle(0, truth.center + 0.125 * g, across, 0.175, up, 0.125));
  landmarks.push_back(planemap::testing::Rectangle(1, truth.center - 0.175 * across, g, 0.125, up, 0.125));
  landmarks.push_back(planemap::testing::Rectangle(2, truth.center + 0.125 * up, g, 0.125, across, 0.175));
  for (PlaneLandmark& l : landmarks) l.observations = 10;
  mapped.landmarks = {0, 1, 2};
  const Eigen::Vector2d side = g.head<2>();
  const MapObject anchored = AnchoredToMappedFaces(mapped, landmarks, config);
  EXPECT_NEAR((anchored.center - truth.center).norm() * 100.0, 0.0, 1e-6);
  const Pose2 pose = PreGraspPose(anchored, config, side), right = PreGraspPose(truth, config, side);
  EXPECT_NEAR((pose.Position() - right.Position()).norm() * 100.0, 0.0, 1e-6);
  EXPECT_NEAR((PreGraspPose(mapped, config, side).Position() - right.Position()).norm() * 100.0,
              100.0 * std::hypot(0.06, 0.04), 1e-6);

  // Along g, no face that can be trusted: the map's centre is kept along g, moved across it.
  const auto along_g = [&](const std::vector<PlaneLandmark>& faces) {
    const MapObject a = AnchoredToMappedFaces(mapped, faces, config);
    EXPECT_NEAR((a.center - truth.center).dot(across) * 100.0, 0.0, 1e-6);
    return (a.center - mapped.center).dot(g) * 100.0;
  };
  std::vector<PlaneLandmark> few = landmarks;
  few[0].observations = config.face_anchor_min_views - 1;  // seen too few times
  EXPECT_NEAR(along_g(few), 0.0, 1e-9);
  std::vector<PlaneLandmark> tilted = landmarks;  // 20 deg off the face
  const Eigen::Vector3d turned = Eigen::AngleAxisd(20.0 * kDeg, up) * g;
  tilted[0].plane = Plane{turned, -turned.dot(truth.center + 0.125 * g)};
  EXPECT_NEAR(along_g(tilted), 0.0, 1e-9);
  std::vector<PlaneLandmark> beyond = landmarks;  // farther from the centre than the whole depth
  beyond[0].plane = Plane{g, -g.dot(mapped.center + 0.26 * g)};
  EXPECT_NEAR(along_g(beyond), 0.0, 1e-9);
  std::vector<PlaneLandmark> far_side = landmarks;  // the -x face, 2 cm nearer the centre than 12.5 cm
  far_side[0].plane = Plane{-g, g.dot(mapped.center - 0.105 * g)};
  EXPECT_NEAR(along_g(far_side), 2.0, 1e-6);
  // No landmarks at all (ids out of range): unchanged.
  EXPECT_EQ((AnchoredToMappedFaces(mapped, {}, config).center - mapped.center).norm(), 0.0);
}

TEST(Grasp, ConfigIsValidated) {
  GraspConfig config;
  EXPECT_NO_THROW(ValidateConfig(config));
  config.reach_max = -0.1;
  EXPECT_THROW(ValidateConfig(config), std::invalid_argument);
}

}  // namespace
}  // namespace planemap::nav
