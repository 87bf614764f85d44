// Object evaluation: matching map objects to scene objects, centre, dimension and axis errors.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "planemap/core/object_eval.h"
#include "test_support.h"

namespace planemap {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A 0.35 x 0.25 x 0.25 m box at (2, 0.5, 0.125) turned 30 deg about z.
ObjectTruth Box() {
  return {"box", "box", MakePoseRpy(0.0, 0.0, 30.0 * kDeg, Eigen::Vector3d(2.0, 0.5, 0.125)),
          Eigen::Vector3d(0.35, 0.25, 0.25)};
}

// The box as a map holds it: x the normal of its largest vertical face (0.35 x 0.25 m, normal
// along the box's y), so the map's x and y are the box's y and x.
ObjectEstimate Estimate(const ObjectTruth& truth) {
  ObjectEstimate estimate;
  estimate.label = "box";
  const Eigen::Matrix3d R = truth.T_world_object.linear();
  estimate.axes << -R.col(1), R.col(0), R.col(2);
  estimate.dimensions = Eigen::Vector3d(truth.dimensions.y(), truth.dimensions.x(), truth.dimensions.z());
  estimate.dimension_complete = {true, true, true};
  estimate.center = truth.T_world_object.translation();
  estimate.grasp_axis = -R.col(1);
  return estimate;
}

EvalConfig Config() { return EvalConfig{}; }

TEST(EvaluateObjects, ExactEstimateHasZeroErrors) {
  const std::vector<ObjectError> errors = EvaluateObjects({Box()}, {Estimate(Box())}, Config());
  ASSERT_EQ(errors.size(), 1u);
  ASSERT_TRUE(errors[0].found());
  EXPECT_NEAR(errors[0].center_error, 0.0, 1e-12) << "[m]";
  EXPECT_LT(errors[0].dimension_error.cwiseAbs().maxCoeff(), 1e-12) << "[m]";
  EXPECT_NEAR(errors[0].axis_error_deg, 0.0, 1e-6);
  EXPECT_NEAR(errors[0].grasp_axis_error_deg, 0.0, 1e-6);
}

TEST(EvaluateObjects, KnownErrorsAreMeasured) {
  ObjectEstimate estimate = Estimate(Box());
  estimate.center += Eigen::Vector3d(0.01, -0.02, 0.0);  // 2.24 cm
  estimate.dimensions += Eigen::Vector3d(0.005, -0.01, 0.02);
  estimate.dimension_complete = {true, true, false};
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(4.0 * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  estimate.axes = turn * estimate.axes;
  estimate.grasp_axis = Eigen::AngleAxisd(-88.0 * kDeg, Eigen::Vector3d::UnitZ()) * *estimate.grasp_axis;
  const ObjectError error = EvaluateObjects({Box()}, {estimate}, Config())[0];
  EXPECT_NEAR(error.center_error * 100.0, std::sqrt(5.0), 1e-9) << "centre [cm]";
  EXPECT_NEAR(error.dimension_error.x() * 100.0, 0.5, 1e-9) << "dimension along x [cm]";
  EXPECT_NEAR(error.dimension_error.y() * 100.0, -1.0, 1e-9) << "dimension along y [cm]";
  EXPECT_TRUE(std::isnan(error.dimension_error.z())) << "an incomplete edge has no error";
  EXPECT_NEAR(error.axis_error_deg, 4.0, 1e-9) << "[deg]";
  EXPECT_NEAR(error.grasp_axis_error_deg, 2.0, 1e-9) << "88 deg off one face normal is 2 deg off the next [deg]";
}

TEST(EvaluateObjects, FarOrMissingObjectsAreNotFoundAndOtherTypesAreSkipped) {
  ObjectTruth locker{"locker2", "locker", MakePoseRpy(0, 0, 0, Eigen::Vector3d(0.0, 2.0, 0.9)),
                     Eigen::Vector3d(0.5, 0.8, 1.8)};
  ObjectTruth desk{"desk", "furniture", Pose3::Identity(), Eigen::Vector3d(1.0, 2.0, 0.7)};
  ObjectEstimate far = Estimate(Box());
  far.center = locker.T_world_object.translation() + Eigen::Vector3d(0.6, 0.0, 0.0);  // beyond 0.5 m
  const std::vector<ObjectError> errors = EvaluateObjects({Box(), locker, desk}, {far, Estimate(Box())}, Config());
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_EQ(errors[0].name, "box");
  EXPECT_EQ(errors[0].estimate, 1);
  EXPECT_EQ(errors[1].name, "locker2");
  EXPECT_FALSE(errors[1].found());
  EXPECT_TRUE(std::isnan(errors[1].center_error));
}

TEST(EvaluateObjects, EachEstimateMatchesOneTruthNearestFirst) {
  // Two boxes 0.4 m apart and one estimate 0.1 m from the second: only the second gets it.
  ObjectTruth second = Box();
  second.name = "box2";
  second.T_world_object.translation() += Eigen::Vector3d(0.4, 0.0, 0.0);
  ObjectEstimate estimate = Estimate(second);
  estimate.center += Eigen::Vector3d(-0.1, 0.0, 0.0);
  const std::vector<ObjectError> errors = EvaluateObjects({Box(), second}, {estimate}, Config());
  EXPECT_FALSE(errors[0].found());
  ASSERT_TRUE(errors[1].found());
  EXPECT_NEAR(errors[1].center_error * 100.0, 10.0, 1e-9) << "[cm]";
}

TEST(EvaluateObjects, TransformedEstimateMovesCentreAndAxes) {
  const Pose3 T = MakePoseRpy(0.0, 0.0, 90.0 * kDeg, Eigen::Vector3d(1.0, 0.0, 0.0));
  const ObjectEstimate exact = Estimate(Box());
  const ObjectEstimate moved = Transformed(T.inverse(), exact);
  const ObjectError error = EvaluateObjects({Box()}, {Transformed(T, moved)}, Config())[0];
  EXPECT_NEAR(error.center_error, 0.0, 1e-12) << "[m]";
  EXPECT_NEAR(error.axis_error_deg, 0.0, 1e-6);
  EXPECT_NEAR(error.grasp_axis_error_deg, 0.0, 1e-6);
}

}  // namespace
}  // namespace planemap
