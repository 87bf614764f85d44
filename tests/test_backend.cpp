// The back end on rendered walks (full sensor noise, seeded): batch refinement against the same
// run without it (ATE, box dimensions), the sliding window against tracking, and the box
// dimensions' covariance against their errors.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "planemap/backend/backend.h"
#include "planemap/core/object_eval.h"
#include "planemap/core/trajectory_eval.h"
#include "planemap/sim/scene.h"
#include "test_support.h"
#include "tracked_walk.h"

namespace planemap {
namespace {

using testing::SourcePath;
using testing::TrackedRun;
using testing::TrackWalk;

struct WalkCase {
  testing::SceneWalk walk;
  // The batch lowers the ATE by 30% (or ends where it ends started at the true poses); it is
  // never worse.
  bool ate_goal;
  // The batch lowers the box's mean dimension error by 30%: where tracking's sizes were off by
  // more than a millimetre (on the default and storeroom walks they are within 0.6 mm, under a
  // pixel; what is left is the silhouette's dropped pixels, which every view shares).
  bool dimension_goal;
};

double Ate(const Trajectory& truth, const Trajectory& estimate) {
  return EvaluateTrajectory(truth, estimate, EvalConfig{}, "truth", "estimate").ate.translation.rmse;
}

const ObjectError* BoxError(const std::vector<ObjectError>& errors, const char* name) {
  for (const ObjectError& e : errors) {
    if (e.name == name && e.found()) return &e;
  }
  return nullptr;
}

class RefinedWalk : public ::testing::TestWithParam<WalkCase> {};

TEST_P(RefinedWalk, BatchLowersAteAndBoxErrorWindowNeverWorse) {
  const WalkCase& param = GetParam();
  const testing::SceneWalk& c = param.walk;
  const sim::Scene scene = sim::LoadScene(SourcePath(c.scene));
  const TrackedRun run = TrackWalk(scene, c.waypoints, 11);
  const BatchResult batch = RefineBatch(run.map, run.observations, BackendConfig{});
  std::printf("%s\n", batch.report.brief.c_str());
  Trajectory refined;
  for (size_t i = 0; i < batch.poses.size(); ++i) refined.push_back({run.estimate[i].stamp, batch.poses[i]});

  // The same problem started at the true poses: where the data put the optimum.
  std::vector<FrameObservations> from_truth = run.observations;
  for (size_t i = 0; i < from_truth.size(); ++i) from_truth[i].T_world_camera = run.truth[i].T_world_camera;
  const BatchResult optimum = RefineBatch(run.map, from_truth, BackendConfig{});
  Trajectory refined_from_truth;
  for (size_t i = 0; i < optimum.poses.size(); ++i) refined_from_truth.push_back({run.estimate[i].stamp, optimum.poses[i]});

  const double ate_tracking = Ate(run.truth, run.estimate), ate_batch = Ate(run.truth, refined),
               ate_window = Ate(run.truth, run.smoothed), ate_optimum = Ate(run.truth, refined_from_truth);
  std::printf("%s: ATE tracking %.2f mm, sliding window %.2f mm, batch %.2f mm (%s, %d iterations, %.3f s; "
              "started at the true poses %.2f mm)\n", c.scene,
              1000 * ate_tracking, 1000 * ate_window, 1000 * ate_batch, batch.report.linear_solver.c_str(), batch.report.iterations,
              batch.report.seconds, 1000 * ate_optimum);
  const auto before = EvaluateObjects(sim::ObjectTruths(scene), MapObjectEstimates(run.map), EvalConfig{});
  const auto after = EvaluateObjects(sim::ObjectTruths(scene), MapObjectEstimates(batch.map), EvalConfig{});
  const ObjectError* b = BoxError(before, c.box);
  const ObjectError* a = BoxError(after, c.box);
  ASSERT_TRUE(b && a);
  const MapObject& o = batch.map.objects[a->estimate];
  std::printf("  %s: dimensions %+.1f %+.1f %+.1f mm -> %+.1f %+.1f %+.1f mm (std %.1f %.1f %.1f mm), centre %.1f -> %.1f mm, axis %.2f -> %.2f deg\n",
              c.box, 1000 * b->dimension_error.x(), 1000 * b->dimension_error.y(), 1000 * b->dimension_error.z(),
              1000 * a->dimension_error.x(), 1000 * a->dimension_error.y(), 1000 * a->dimension_error.z(),
              1000 * o.uncertainty.dimension_std.x(), 1000 * o.uncertainty.dimension_std.y(), 1000 * o.uncertainty.dimension_std.z(),
              1000 * b->center_error, 1000 * a->center_error, b->axis_error_deg, a->axis_error_deg);
  EXPECT_LE(ate_window, ate_tracking) << "m: the sliding window never worse than the tracking it smooths";
  // 30% lower, or (tracking already near what the data allow) within 5% of the batch started at
  // the true poses: on the default walk it is 1.87 mm, and tracking at 2.5 mm leaves no 30%.
  EXPECT_LE(ate_batch, param.ate_goal ? std::max(0.7 * ate_tracking, 1.05 * ate_optimum) : ate_tracking) << "m";
  // And never worse than tracking, whatever the optimum: an optimum worse than tracking is the data
  // pulling it off (the office walk's batch was once 3.57 mm against tracking's 2.81, its optimum
  // 4.95 mm: a shelf side whose plane took in the board's front edge, docs/frontend.md).
  EXPECT_LE(ate_batch, ate_tracking) << "m";
  if (param.dimension_goal) {
    EXPECT_LE(a->dimension_error.cwiseAbs().mean(), 0.7 * b->dimension_error.cwiseAbs().mean()) << "m";
  }
  // Never worse than tracking's sizes; the centre (from the box's faces, not eq. 7's corners)
  // and the axis no worse than tracking's beyond 3 of its own standard deviations (a hundredth
  // of a degree: tracking's axis, one landmark's normal, can be that close by chance); every
  // dimension measured, within 3 standard deviations of the truth.
  EXPECT_LE(a->dimension_error.cwiseAbs().mean(), b->dimension_error.cwiseAbs().mean() + 0.0002) << "m";
  EXPECT_LE(a->center_error, 0.7 * b->center_error) << "m";
  ASSERT_TRUE(o.uncertainty.known) << batch.covariance_error;
  ASSERT_GT(o.uncertainty.grasp_axis_std_deg, 0.0);
  EXPECT_LE(a->axis_error_deg, b->axis_error_deg + std::max(0.01, 3.0 * o.uncertainty.grasp_axis_std_deg)) << "deg";
  for (int k = 0; k < 3; ++k) {
    ASSERT_GT(o.uncertainty.dimension_std[k], 0.0) << "axis " << k << " is only bounded";
    EXPECT_LE(std::abs(a->dimension_error[k]), 3.0 * o.uncertainty.dimension_std[k]) << "m, axis " << k;
  }
}

std::string SceneName(const ::testing::TestParamInfo<WalkCase>& info) {
  return testing::SceneStem(info.param.walk);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, RefinedWalk,
    ::testing::Values(WalkCase{testing::SceneWalks()[0], true, false}, WalkCase{testing::SceneWalks()[1], true, false},
                      WalkCase{testing::SceneWalks()[2], true, true}),
    SceneName);

}  // namespace
}  // namespace planemap
