// The pre-grasp pose and the grasp check on the default scene's box (configs/scenes/default.yaml:
// centre (2.1, 0.1, 0.125) m, yaw 215 deg, depth 0.25 x width 0.35 x height 0.25 m).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

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

TEST(Grasp, PreGraspPoseOfTheDefaultBox) {
  const MapObject box = DefaultBox();
  const GraspConfig config;
  const Pose2 pose = PreGraspPose(box, config, kTowardStart);
  // 23.5 cm out of the +x face's centre line, facing the box: heading 215 - 180 = 35 deg.
  EXPECT_NEAR(pose.x, 2.1 + 0.235 * std::cos(215.0 * kDeg), 1e-9);
  EXPECT_NEAR(pose.y, 0.1 + 0.235 * std::sin(215.0 * kDeg), 1e-9);
  EXPECT_NEAR(pose.theta / kDeg, 35.0, 1e-9);
  const GraspGeometry faces = GraspFaces(box, kTowardStart);
  EXPECT_NEAR(faces.width * 100.0, 35.0, 1e-9);
  EXPECT_NEAR(faces.depth * 100.0, 25.0, 1e-9);
  // The near face 11 cm ahead of the base origin: at least body_clearance (toes 8 cm, a 3 cm gap).
  EXPECT_NEAR((0.235 - 0.5 * faces.depth) * 100.0, 11.0, 1e-9);
  EXPECT_GE((0.235 - 0.5 * faces.depth), config.body_clearance);
  // Grasp points on the side faces, at the centre's height, left of the robot on its left.
  const GraspCheck check = CheckGrasp(box, pose, config);
  EXPECT_TRUE(check.ok) << check.reason;
  EXPECT_NEAR(check.left_point.x() * 100.0, 23.5, 1e-6);
  EXPECT_NEAR(check.left_point.y() * 100.0, 17.5, 1e-6);
  EXPECT_NEAR(check.right_point.y() * 100.0, -17.5, 1e-6);
  EXPECT_NEAR(check.left_point.z() * 100.0, 12.5, 1e-6);
  EXPECT_NEAR(check.left_distance, check.right_distance, 1e-9);
  EXPECT_NEAR((faces.left - box.center).norm() * 100.0, 17.5, 1e-9);
}

TEST(Grasp, WithoutAGraspAxisTheSideFacingTheRobotIsUsed) {
  MapObject box = DefaultBox();
  box.has_grasp_axis = false;
  const GraspConfig config;
  const Pose2 same = PreGraspPose(box, config, kTowardStart);
  EXPECT_NEAR(same.theta / kDeg, 35.0, 1e-9);
  // From +y the box's -y face is nearest; 35 cm deep that way: body clearance sets the standoff.
  const Pose2 side = PreGraspPose(box, config, {0.0, 1.0});
  EXPECT_NEAR(WrapAngle(side.theta) / kDeg, WrapAngle((215.0 - 90.0 - 180.0) * kDeg) / kDeg, 1e-9);
  EXPECT_NEAR((side.Position() - box.center.head<2>()).norm() * 100.0,
              (0.175 + config.body_clearance) * 100.0, 1e-9);
  EXPECT_NEAR(GraspFaces(box, {0.0, 1.0}).width * 100.0, 25.0, 1e-9);
  EXPECT_TRUE(CheckGrasp(box, side, config).ok) << CheckGrasp(box, side, config).reason;
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
// Standing 3 cm clear of the box costs reach: 3 cm farther back and turned 5 deg, a hand needs
// 27 cm (reach_max 26.5 cm).
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

TEST(Grasp, ConfigIsValidated) {
  GraspConfig config;
  EXPECT_NO_THROW(ValidateConfig(config));
  config.reach_max = -0.1;
  EXPECT_THROW(ValidateConfig(config), std::invalid_argument);
}

}  // namespace
}  // namespace planemap::nav
