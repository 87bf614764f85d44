// Tracking and mapping on rendered walks (full sensor noise, seeded): ATE against the walk's
// ground truth, no lost frame, the box's map dimensions and axis against the scene; and a walk
// that faces a bare wall for a while is marked degraded there and recovers; a standing robot does
// not follow a far wall seen edge-on; a wall seen again after a turn over open floor corrects the
// heading instead of being mapped twice.
// PLANEMAP_TRACE=1 prints every frame's status and error.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "planemap/core/object_eval.h"
#include "planemap/core/trajectory_eval.h"
#include "planemap/frontend/frontend.h"
#include "planemap/frontend/silhouette.h"
#include "planemap/frontend/tracker.h"
#include "planemap/io/tum_sequence.h"
#include "planemap/nav/simulated_humanoid.h"
#include "planemap/sim/walk.h"
#include "sim_views.h"
#include "test_support.h"
#include "tracked_walk.h"

namespace planemap {
namespace {

using testing::SourcePath;
using testing::TrackedRun;
using testing::TrackWalk;

class TrackedWalk : public ::testing::TestWithParam<testing::SceneWalk> {};

TEST_P(TrackedWalk, AteUnderTwoCentimetresNoFrameLostBoxSizeAndAxis) {
  const testing::SceneWalk& c = GetParam();
  const sim::Scene scene = sim::LoadScene(SourcePath(c.scene));
  const TrackedRun run = TrackWalk(scene, c.waypoints, 11);
  int degraded = 0, lost = 0;
  for (TrackStatus s : run.status) degraded += s == TrackStatus::kDegraded, lost += s == TrackStatus::kLost;
  EvalConfig eval;
  eval.rpe_delta = 1.0;
  const TrajectoryEvaluation t = EvaluateTrajectory(run.truth, run.estimate, eval, "truth", "estimate");
  double length = 0.0;
  for (size_t k = 1; k < run.truth.size(); ++k) {
    length += (run.truth[k].T_world_camera.translation() - run.truth[k - 1].T_world_camera.translation()).norm();
  }
  std::printf("%s: %zu frames over %.2f m of camera path; degraded %d, lost %d; ATE RMSE %.1f mm (max %.1f); "
              "RPE/1 s %.1f mm, %.2f deg; map %zu planes, %zu objects, %.1f kB\n",
              c.scene, run.status.size(), length, degraded, lost, 1000 * t.ate.translation.rmse,
              1000 * t.ate.translation.max, 1000 * t.rpe.translation.rmse, t.rpe.rotation.rmse, run.map.landmarks.size(),
              run.map.objects.size(), run.map.MemoryBytes() / 1024.0);
  EXPECT_GE(length, 3.0) << "m";
  EXPECT_EQ(lost, 0);
  EXPECT_LE(t.ate.translation.rmse, 0.02) << "m";

  // The map is in the ground truth's world (first pose anchored): no alignment for objects.
  const std::vector<ObjectError> errors = EvaluateObjects(sim::ObjectTruths(scene), MapObjectEstimates(run.map), EvalConfig{});
  bool checked = false;
  for (const ObjectError& e : errors) {
    if (!e.found()) {
      std::printf("  %s (%s): not in the map\n", e.name.c_str(), e.type.c_str());
      continue;
    }
    const MapObject& o = run.map.objects[e.estimate];
    std::printf("  %s (%s): map %s seen %d times, centre %.1f mm, dimensions %+.1f %+.1f %+.1f mm, axis %.2f deg\n",
                e.name.c_str(), e.type.c_str(), o.label.c_str(), o.observations, 1000 * e.center_error,
                1000 * e.dimension_error.x(), 1000 * e.dimension_error.y(), 1000 * e.dimension_error.z(), e.axis_error_deg);
    if (e.name != c.box) continue;
    checked = true;
    EXPECT_EQ(o.label, "box");
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(o.dimension_complete[k]) << "axis " << k;
      if (o.dimension_complete[k]) {
        EXPECT_LE(std::abs(e.dimension_error[k]), 0.01) << "m, axis " << k;
      }
    }
    EXPECT_LE(e.axis_error_deg, 2.0) << "deg";
  }
  EXPECT_TRUE(checked) << c.box << " is in the map";
}

std::string SceneName(const ::testing::TestParamInfo<testing::SceneWalk>& info) {
  return testing::SceneStem(info.param);
}

INSTANTIATE_TEST_SUITE_P(Scenes, TrackedWalk, ::testing::ValuesIn(testing::SceneWalks()), SceneName);

TEST(Tracking, RealSequenceRunsEndToEndAndPrintsAte) {
  // TUM fr1/rpy, 100 frames of a handheld Kinect mostly rotating (1-4 deg per frame) in an
  // office: no threshold on the ATE is asked for yet; the test prints it. It asserts that every
  // frame gets a pose and a status, that the tracker measures (not only predicts) most of them,
  // and that the tracked poses are near the ground truth's (anchored at the first).
  PLANEMAP_REQUIRE_SHARED("data/tum_fr1_rpy_slice");
  const std::string dir = testing::SharedPath("data/tum_fr1_rpy_slice");
  const CameraIntrinsics camera = LoadCameraIntrinsics(SourcePath("configs/cameras/tum_fr1.yaml"));
  const TumSequence sequence = TumSequence::Open(dir, camera, DatasetConfig{});
  const Frontend frontend(camera, FrontendConfig{}, LoadPatterns(SourcePath("configs/patterns.yaml")));
  ASSERT_TRUE(sequence.entry(0).T_world_camera.has_value());
  Tracker tracker(TrackingConfig{}, *sequence.entry(0).T_world_camera, camera);
  Trajectory truth, estimate;
  int counts[3] = {0, 0, 0};
  for (size_t i = 0; i < sequence.size(); ++i) {
    const RgbdFrame frame = sequence.LoadFrame(i);
    const Cloud::Ptr cloud = MakeOrganizedCloud(frame, camera, CloudConfig{});
    const TrackResult r = tracker.Track(frontend.Process(*cloud), *cloud, frame.stamp);
    ++counts[static_cast<int>(r.status)];
    estimate.push_back({frame.stamp, r.T_world_camera});
    if (sequence.entry(i).T_world_camera) truth.push_back({frame.stamp, *sequence.entry(i).T_world_camera});
  }
  const TrajectoryEvaluation t = EvaluateTrajectory(truth, estimate, EvalConfig{}, "groundtruth", "planemap");
  std::printf("tum_fr1_rpy_slice: %zu frames: tracked %d, degraded %d, lost %d; ATE RMSE %.1f mm (median %.1f, max %.1f); "
              "RPE/1 s %.1f mm, %.2f deg; map %zu planes, %.1f kB\n",
              sequence.size(), counts[0], counts[1], counts[2], 1000 * t.ate.translation.rmse, 1000 * t.ate.translation.median,
              1000 * t.ate.translation.max, 1000 * t.rpe.translation.rmse, t.rpe.rotation.rmse, tracker.map().landmarks.size(),
              tracker.map().MemoryBytes() / 1024.0);
  EXPECT_EQ(estimate.size(), sequence.size());
  EXPECT_EQ(counts[0] + counts[1] + counts[2], static_cast<int>(sequence.size()));
  EXPECT_GT(t.pairs, 90u);
  // Near the ground truth: 34.9 mm now; 75.0 mm when the strips joined across pixels without depth
  // (the segmenter's second search) also took pixels back from the planes the tracker uses.
  EXPECT_LT(t.ate.translation.rmse, 0.05) << "m";
}

// Frames of the default walk 1 s apart (every 5th at 5 Hz): the camera turns up to 30 deg between
// them on the spot, beyond the constant-velocity prediction's 20 deg gates; those poses come from
// plane correspondences found without it (plane_relocalization.h). At 2 s apart the turn's views
// share fewer than three plane directions with the map: those frames are degraded, not mapped.
TEST(Tracking, FramesOneSecondApartAreTrackedWithoutAPrediction) {
  const testing::SceneWalk& walk = testing::SceneWalks().front();
  const TrackedRun run = TrackWalk(sim::LoadScene(SourcePath(walk.scene)), walk.waypoints, 11, 0,
                                   std::numeric_limits<std::size_t>::max(), Pose3::Identity(), BackendConfig{}, 5);
  int tracked = 0, lost = 0, relocalized = 0;
  double largest_turn = 0.0;
  for (size_t k = 0; k < run.status.size(); ++k) {
    tracked += run.status[k] == TrackStatus::kTracked;
    relocalized += run.relocalized[k];
    lost += run.status[k] == TrackStatus::kLost;
    if (k > 0) largest_turn = std::max(largest_turn, testing::RotationErrorDeg(run.truth[k - 1].T_world_camera, run.truth[k].T_world_camera));
  }
  EvalConfig eval;
  eval.rpe_delta = 1.0;  // [s], one frame step
  const TrajectoryEvaluation t = EvaluateTrajectory(run.truth, run.estimate, eval, "truth", "estimate");
  std::printf("default walk every 5th frame (1 s apart, turns up to %.0f deg): %zu frames, tracked %d (relocalized %d), lost %d; ATE RMSE %.1f mm (max %.1f)\n",
              largest_turn, run.status.size(), tracked, relocalized, lost, 1000 * t.ate.translation.rmse, 1000 * t.ate.translation.max);
  EXPECT_GE(largest_turn, 25.0) << "deg: the test needs turns beyond the prediction's 20 deg gates";
  EXPECT_GE(relocalized, 1);
  EXPECT_EQ(lost, 0);
  EXPECT_EQ(tracked, static_cast<int>(run.status.size()));
  EXPECT_LE(t.ate.translation.rmse, 0.02) << "m";
}

// A real sequence tracked with every `stride`-th frame, as `planemap map --stride` does.
struct RealRun {
  AteResult ate;
  int tracked = 0, degraded = 0, lost = 0, relocalized = 0;
};
RealRun TrackReal(const std::string& dir, const std::string& camera_file, size_t stride) {
  const CameraIntrinsics camera = LoadCameraIntrinsics(SourcePath(camera_file));
  const TumSequence sequence = TumSequence::Open(dir, camera, DatasetConfig{});
  const Frontend frontend(camera, FrontendConfig{}, LoadPatterns(SourcePath("configs/patterns.yaml")));
  Tracker tracker(TrackingConfig{}, sequence.entry(0).T_world_camera.value_or(Pose3::Identity()), camera);
  Trajectory estimate;
  RealRun run;
  for (size_t i = 0; i < sequence.size(); i += stride) {
    const RgbdFrame frame = sequence.LoadFrame(i);
    const Cloud::Ptr cloud = MakeOrganizedCloud(frame, camera, CloudConfig{});
    const TrackResult r = tracker.Track(frontend.Process(*cloud), *cloud, frame.stamp);
    run.tracked += r.status == TrackStatus::kTracked;
    run.degraded += r.status == TrackStatus::kDegraded;
    run.lost += r.status == TrackStatus::kLost;
    run.relocalized += r.relocalized;
    estimate.push_back({frame.stamp, r.T_world_camera});
  }
  run.ate = ComputeAte(AssociatePoses(sequence.groundtruth(), estimate, EvalConfig{}.max_time_gap));
  return run;
}

// Every 20th frame (0.67 s apart) of the shared sequences whose views overlap by three plane
// directions or more: none lost or degraded, ATE within twice the every-frame figure.
class WideBaseline : public ::testing::TestWithParam<std::pair<const char*, const char*>> {};

TEST_P(WideBaseline, EveryTwentiethFrameIsTrackedWithinTwiceTheAteOfEveryFrame) {
  const std::string dir = testing::SharedPath(std::string("data/") + GetParam().first);
  PLANEMAP_REQUIRE_SHARED(std::string("data/") + GetParam().first);
  const RealRun every = TrackReal(dir, GetParam().second, 1), twentieth = TrackReal(dir, GetParam().second, 20);
  std::printf("%s: stride 1 ATE %.2f cm; stride 20: %d tracked (%d relocalized), %d degraded, %d lost, ATE %.2f cm\n", GetParam().first,
              100 * every.ate.translation.rmse, twentieth.tracked, twentieth.relocalized, twentieth.degraded, twentieth.lost,
              100 * twentieth.ate.translation.rmse);
  EXPECT_EQ(twentieth.lost, 0);
  EXPECT_EQ(twentieth.degraded, 0);
  EXPECT_GT(twentieth.ate.translation.count, 3u);
  EXPECT_LE(twentieth.ate.translation.rmse, 2.0 * every.ate.translation.rmse) << "m";
}

INSTANTIATE_TEST_SUITE_P(Real, WideBaseline,
                         ::testing::Values(std::make_pair("tum_fr3_snt_far_head", "configs/cameras/tum_fr3.yaml"),
                                           std::make_pair("icl_office_kt0", "configs/cameras/icl_nuim.yaml")),
                         [](const auto& info) { return std::string(info.param.first).substr(0, 7) == "tum_fr3" ? std::string("fr3") : std::string("icl"); });

// TUM fr3/long_office_household, two frames 2.3 s apart (30 cm, 6 deg): no prediction reaches
// the second; its pose is found from the planes both see.
TEST(Tracking, TwoRealFramesFarApartAreRelocalized) {
  PLANEMAP_REQUIRE_SHARED("data/tum_frame_pairs/fr3_long_office_household");
  const std::string dir = testing::SharedPath("data/tum_frame_pairs/fr3_long_office_household");
  const CameraIntrinsics camera = LoadCameraIntrinsics(SourcePath("configs/cameras/tum_fr3.yaml"));
  const TumSequence sequence = TumSequence::Open(dir, camera, DatasetConfig{});
  ASSERT_EQ(sequence.size(), 2u);
  const Frontend frontend(camera, FrontendConfig{}, LoadPatterns(SourcePath("configs/patterns.yaml")));
  Tracker tracker(TrackingConfig{}, Pose3::Identity(), camera);
  std::vector<TrackResult> results;
  std::vector<double> stamps;
  for (size_t i = 0; i < 2; ++i) {
    const RgbdFrame frame = sequence.LoadFrame(i);
    const Cloud::Ptr cloud = MakeOrganizedCloud(frame, camera, CloudConfig{});
    results.push_back(tracker.Track(frontend.Process(*cloud), *cloud, frame.stamp));
    stamps.push_back(frame.stamp);
  }
  // The first frame is 67 ms before the ground truth starts (the camera then moves about 3 mm):
  // both frames take the nearest ground-truth pose.
  const auto nearest = [&](double stamp) {
    const Trajectory& truth = sequence.groundtruth();
    return std::min_element(truth.begin(), truth.end(), [&](const StampedPose& a, const StampedPose& b) {
             return std::abs(a.stamp - stamp) < std::abs(b.stamp - stamp);
           })->T_world_camera;
  };
  const Pose3 truth = nearest(stamps[0]).inverse() * nearest(stamps[1]);
  const Pose3 estimate = results[1].T_world_camera;  // the first frame is the world
  std::printf("fr3_long_office pair: true motion %.1f cm, %.1f deg; %s%s, error %.1f cm, %.2f deg\n", 100 * truth.translation().norm(),
              RotationAngle(truth.linear()) * 180.0 / M_PI, ToString(results[1].status), results[1].relocalized ? " (relocalized)" : "",
              100 * testing::TranslationError(estimate, truth), testing::RotationErrorDeg(estimate, truth));
  EXPECT_EQ(results[1].status, TrackStatus::kTracked);
  EXPECT_TRUE(results[1].relocalized);
  EXPECT_LE(testing::TranslationError(estimate, truth), 0.05) << "m";
  EXPECT_LE(testing::RotationErrorDeg(estimate, truth), 1.0) << "deg";
}

TEST(Tracking, SingleWallStretchIsDegradedAndRecovers) {
  // From the start, a turn to walk at the bare south wall (only the floor and that wall in view:
  // the translation along the wall is unobservable), then a turn back toward the box.
  const sim::Scene scene = sim::LoadScene(SourcePath("configs/scenes/default.yaml"));
  const TrackedRun run = TrackWalk(scene, {0.0, 0.0, 0.6, 0.0, 0.6, -1.6, 1.4, -0.2}, 12);
  int first_degraded = -1, last_degraded = -1, degraded = 0, lost = 0;
  for (size_t k = 0; k < run.status.size(); ++k) {
    if (run.status[k] == TrackStatus::kDegraded) {
      ++degraded;
      if (first_degraded < 0) first_degraded = static_cast<int>(k);
      last_degraded = static_cast<int>(k);
    }
    lost += run.status[k] == TrackStatus::kLost;
  }
  const TrajectoryEvaluation t = EvaluateTrajectory(run.truth, run.estimate, EvalConfig{}, "truth", "estimate");
  // Error at the end, after recovery, straight against the truth (both in the same world).
  const Pose3 end_error = run.truth.back().T_world_camera.inverse() * run.estimate.back().T_world_camera;
  std::printf("single-wall walk: %zu frames, degraded %d (frames %d-%d), lost %d; ATE RMSE %.1f mm; "
              "final error %.1f mm, %.2f deg\n",
              run.status.size(), degraded, first_degraded, last_degraded, lost, 1000 * t.ate.translation.rmse,
              1000 * end_error.translation().norm(), RotationAngle(end_error.linear()) * 180.0 / M_PI);
  EXPECT_GE(degraded, 10) << "the wall stretch is marked degraded";
  EXPECT_EQ(lost, 0);
  ASSERT_GE(last_degraded, 0);
  EXPECT_LT(last_degraded + 10, static_cast<int>(run.status.size())) << "tracking recovers before the end";
  EXPECT_EQ(run.status.back(), TrackStatus::kTracked);
  EXPECT_LE(end_error.translation().norm(), 0.05) << "m after recovery";
  EXPECT_LE(RotationAngle(end_error.linear()) * 180.0 / M_PI, 2.0) << "deg after recovery";
}

// A rendered view of `scene` (sensor noise seeded by `seed` and the frame index k) tracked as a
// camera would deliver it: the organized cloud and the frontend's model of it.
class RenderedViews {
 public:
  RenderedViews(const std::string& scene, int seed, const FrontendConfig& frontend = FrontendConfig{})
      : scene_(sim::LoadScene(SourcePath(scene))),
        camera_(scene_, testing::XtionCamera(), [seed] {
          sim::RenderConfig render;
          render.seed = seed;
          return render;
        }()),
        frontend_(testing::XtionCamera(), frontend, LoadPatterns(SourcePath("configs/patterns.yaml"))) {}

  // The organized cloud of the view from T_world_camera (frame k's noise) and the frontend's model of it.
  std::pair<Cloud::Ptr, FrameModel> View(const Pose3& T_world_camera, int k) const {
    sim::RenderedFrame rendered = camera_.Render(T_world_camera, camera_.FrameSeed(k));
    RgbdFrame frame;
    frame.depth = std::move(rendered.depth);
    const Cloud::Ptr cloud = MakeOrganizedCloud(frame, testing::XtionCamera(), CloudConfig{});
    FrameModel model = frontend_.Process(*cloud);
    return {cloud, std::move(model)};
  }

  TrackResult Track(Tracker& tracker, const Pose3& T_world_camera, int k, double stamp,
                    const std::optional<Pose3>& odometry) const {
    const auto [cloud, model] = View(T_world_camera, k);
    return tracker.Track(model, *cloud, stamp, odometry);
  }

  const sim::Scene& scene() const { return scene_; }

 private:
  sim::Scene scene_;
  sim::VirtualCamera camera_;
  Frontend frontend_;
};

// A camera walks 30 cm along the bare south wall of the default scene with only that wall and the
// floor in view: the planes fix everything but the motion along the wall. Without odometry the
// prediction (constant velocity, from standing) stays where the walk began; with the walking
// engine's odometry (here the true motion seen from a drifted odometry frame, scaled by a 5%
// error as a humanoid's) the tracker follows it.
TEST(Tracking, WhereNoPlaneFixesThePoseItFollowsTheOdometry) {
  const RenderedViews views("configs/scenes/default.yaml", 5);
  const auto truth = [](int k) {
    const Eigen::Vector3d eye(0.5 + 0.015 * k, -1.8, 0.6);
    return testing::LookAt(eye, eye + Eigen::Vector3d(0.0, -1.0, -0.35));
  };
  Pose3 T_odometry_world = Pose3::Identity();
  T_odometry_world.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T_odometry_world.translation() = Eigen::Vector3d(3.0, -2.0, 0.0);
  const int frames = 21;
  double error[2] = {0.0, 0.0};
  int degraded[2] = {0, 0};
  for (int with_odometry = 0; with_odometry < 2; ++with_odometry) {
    Tracker tracker(TrackingConfig{}, truth(0));
    for (int k = 0; k < frames; ++k) {
      std::optional<Pose3> odometry;
      if (with_odometry) {
        Pose3 T = truth(k);
        T.translation() = truth(0).translation() + 1.05 * (T.translation() - truth(0).translation());
        odometry = T_odometry_world * T;
      }
      const TrackResult r = views.Track(tracker, truth(k), k, 0.2 * k, odometry);
      degraded[with_odometry] += r.status == TrackStatus::kDegraded;
      if (k == frames - 1) error[with_odometry] = (r.T_world_camera.translation() - truth(k).translation()).norm();
    }
  }
  std::printf("30 cm along a bare wall: final error without odometry %.1f cm (%d degraded frames), with %.1f cm (%d)\n",
              100 * error[0], degraded[0], 100 * error[1], degraded[1]);
  EXPECT_GE(degraded[0], frames - 2) << "only the wall and the floor in view";
  EXPECT_GE(degraded[1], frames - 2);
  EXPECT_GT(error[0], 0.20) << "m: without odometry the motion along the wall is not seen";
  EXPECT_LT(error[1], 0.02) << "m: 5% of 30 cm";
}

// The atelier's start: a 1 m shelf 0.6 m ahead fills the view, one plane, which leaves the
// rotation about its normal unmeasured. Without odometry the pose is lost after lost_after frames;
// with the walking engine's odometry the heading errs only as the robot moves, so a robot standing
// there keeps its pose (it may turn to look around), and it is lost once the odometry walked
// lost_after_distance (here an odometry that drifts 5 mm a frame sideways while the robot stands).
TEST(Tracking, FacingOnePlaneWithOdometryThePoseIsLostByMotionNotByFrames) {
  const RenderedViews views("configs/scenes/atelier.yaml", 1);
  const Pose3 T_world_camera = nav::NominalCameraPose(nav::Pose2{}, nav::HumanoidConfig{});
  const TrackingConfig config;
  const int frames = 3 * config.lost_after;
  int first_lost[3] = {-1, -1, -1};
  double error = 0.0;
  for (int run = 0; run < 3; ++run) {  // 0: no odometry, 1: standing odometry, 2: drifting odometry
    Tracker tracker(config, T_world_camera);
    for (int k = 0; k < frames; ++k) {
      std::optional<Pose3> odometry;
      if (run == 1) odometry = T_world_camera;
      if (run == 2) odometry = Pose3(Eigen::Translation3d(0.0, 0.005 * k, 0.0)) * T_world_camera;
      const TrackResult r = views.Track(tracker, T_world_camera, k, k / 15.0, odometry);
      if (r.status == TrackStatus::kLost && first_lost[run] < 0) first_lost[run] = k;
      if (run == 1) error = std::max(error, (r.T_world_camera.translation() - T_world_camera.translation()).norm());
      if (k == 0) {
        EXPECT_EQ(r.planes, 1) << "the shelf's front only";
      }
    }
  }
  std::printf("facing the atelier's shelf %d frames: first lost frame without odometry %d, standing with odometry %d "
              "(largest position error %.2f cm), odometry drifting 5 mm a frame %d\n",
              frames, first_lost[0], first_lost[1], 100.0 * error, first_lost[2]);
  EXPECT_EQ(first_lost[0], config.lost_after + 1);
  EXPECT_EQ(first_lost[1], -1);
  EXPECT_LT(error, 0.01) << "m";
  // Lost once the odometry walked more than lost_after_distance (0.30 m: frame 61 at 5 mm a frame).
  EXPECT_NEAR(first_lost[2], config.lost_after_distance / 0.005 + 1, 1.0);
}

// A robot facing open floor in a large room (a generated room's start may show nothing else):
// the floor alone holds no heading, so with odometry the heading is the odometry's and the pose is
// not lost however far the robot walks (90 frames, 1 cm a frame: three times lost_after_distance);
// without odometry the rotation is the motion model's guess and the pose is lost after lost_after.
TEST(Tracking, OnOpenFloorWithOdometryTheHeadingIsTheOdometrysAndNotLost) {
  const RenderedViews views("configs/scenes/hall.yaml", 1);
  Pose3 start = nav::NominalCameraPose(nav::Pose2{3.0, -1.5, M_PI}, nav::HumanoidConfig{});
  start.linear() = start.linear() * Eigen::AngleAxisd(-45.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()).matrix();  // 65 deg down
  const TrackingConfig config;
  const int frames = 3 * config.lost_after;
  int first_lost[2] = {-1, -1};
  double error = 0.0;
  for (int run = 0; run < 2; ++run) {  // 0: no odometry, 1: odometry
    Tracker tracker(config, start);
    for (int k = 0; k < frames; ++k) {
      const Pose3 truth = Pose3(Eigen::Translation3d(-0.01 * k, 0.0, 0.0)) * start;
      std::optional<Pose3> odometry;
      if (run == 1) odometry = truth;
      const TrackResult r = views.Track(tracker, truth, k, k / 15.0, odometry);
      if (k == 0) {
        EXPECT_EQ(r.planes, 1) << "the floor only";
      }
      if (r.status == TrackStatus::kLost && first_lost[run] < 0) first_lost[run] = k;
      if (run == 1) error = std::max(error, (r.T_world_camera.translation() - truth.translation()).norm());
    }
  }
  std::printf("walking 0.9 m over open floor: first lost frame without odometry %d, with odometry %d (largest "
              "position error %.2f cm)\n",
              first_lost[0], first_lost[1], 100.0 * error);
  EXPECT_EQ(first_lost[0], config.lost_after + 1);
  EXPECT_EQ(first_lost[1], -1);
  EXPECT_LT(error, 0.01) << "m";
}

// The gallery's start (configs/scenes/gallery.yaml, seed 13): the floor, the crate's face 0.9 m
// ahead and the locker's side 3.6 m away, a sliver at the image's corner. With the segmenter's
// robust check off (frontend.segmentation.organized.robust_check_share), the sliver takes in the
// wall behind it in some frames and its normal comes out up to 19 deg off. The rotation of a
// frame that no pose explains (degraded) came from all its planes' normals together, and the
// sliver turned the standing robot 4.6 deg in the second frame; the map followed. Now it is the
// rotation most planes agree with.
TEST(Tracking, AStandingRobotIsNotTurnedByOnePlaneWhoseNormalJumps) {
  FrontendConfig unchecked;
  unchecked.segmentation.organized.robust_check_share = 1.0;
  const RenderedViews views("configs/scenes/gallery.yaml", 13, unchecked);
  const Pose3 T_world_camera = nav::NominalCameraPose(nav::Pose2{}, nav::HumanoidConfig{});
  Tracker tracker(TrackingConfig{}, T_world_camera);
  double position = 0.0, heading = 0.0;
  int degraded = 0;
  for (int k = 0; k < 45; ++k) {  // 3 s at 15 Hz, with the standing robot's odometry
    const TrackResult r = views.Track(tracker, T_world_camera, k, k / 15.0, T_world_camera);
    position = std::max(position, (r.T_world_camera.translation() - T_world_camera.translation()).norm());
    heading = std::max(heading, RotationAngle(T_world_camera.linear().transpose() * r.T_world_camera.linear()));
    degraded += r.status == TrackStatus::kDegraded;
  }
  std::printf("standing 3 s at the gallery's start: %d degraded frames; largest position error %.2f cm, rotation %.2f deg\n",
              degraded, 100 * position, heading * 180.0 / M_PI);
  EXPECT_GT(degraded, 0) << "the frames this is about";
  EXPECT_LT(heading * 180.0 / M_PI, 0.5) << "deg";
  EXPECT_LT(position, 0.01) << "m";
}

// Where the hall's scenario 3 runs end: the box's pre-grasp pose as planned [m, rad].
const nav::Pose2 kHallPreGrasp{1.745, 0.226, 64.9 * M_PI / 180.0};

// The hall's pre-grasp pose (hall scenario 3 runs end here): the floor, the box's top, the north
// wall and, 4.3 m off and edge-on, a strip of the east wall, the only plane that fixes east-west.
// Its fitted normal is off by 2-20 deg and differs in every frame; a standing robot's pose must
// not follow it (it walked 11 cm east in hall seed 6 before tracking.max_normal_std_deg).
TEST(Tracking, AStandingRobotDoesNotFollowAFarWallSeenEdgeOn) {
  const RenderedViews views("configs/scenes/hall.yaml", 6);
  // The humanoid's head camera, standing at the pre-grasp pose the hall runs plan.
  const Pose3 T_world_camera =
      nav::NominalCameraPose(kHallPreGrasp, nav::HumanoidConfig{});
  const Eigen::Vector3d eye = T_world_camera.translation();
  const int frames = 45;  // 3 s at 15 Hz
  double error[2] = {0.0, 0.0};
  for (int gated = 0; gated < 2; ++gated) {
    TrackingConfig config;
    if (!gated) config.max_normal_std_deg = 180.0;
    Tracker tracker(config, T_world_camera);
    for (int k = 0; k < frames; ++k) {
      const TrackResult r = views.Track(tracker, T_world_camera, k, k / 15.0, T_world_camera);
      error[gated] = std::max(error[gated], (r.T_world_camera.translation() - eye).norm());
    }
  }
  std::printf("standing 3 s at the hall's pre-grasp pose: largest position error %.1f cm without the normal "
              "gate, %.1f cm with it\n", 100 * error[0], 100 * error[1]);
  EXPECT_LT(error[1], 0.01) << "m";
}

// The hall's pre-grasp pose: only the far part of the box's top is in view, the near face below
// the image. Where the top ends against the floor beyond, its silhouette pixels lie on the box's
// far and side faces: within a few millimetres of those true faces, never on the image border.
TEST(Tracking, ABoxTopsSilhouetteLiesOnItsSides) {
  const RenderedViews views("configs/scenes/hall.yaml", 3);
  const Pose3 T_world_camera = nav::NominalCameraPose(kHallPreGrasp, nav::HumanoidConfig{});
  const sim::SceneObject& box = views.scene().object("box");
  const auto [cloud, model] = views.View(T_world_camera, 0);
  // The top: the plane whose inliers lie at the box's height, facing up.
  const DetectedPlane* top = nullptr;
  for (const DetectedPlane& p : model.planes) {
    const Plane world = TransformPlane(T_world_camera, p.plane);
    const double height = (T_world_camera * p.centroid).z();
    if (world.normal.z() > 0.99 && std::abs(height - box.dimensions.z()) < 0.02) top = &p;
  }
  ASSERT_NE(top, nullptr) << "the box top is segmented";
  const std::vector<int> pixels = SilhouettePixels(*cloud, top->inliers, 0.03, 3);
  std::vector<double> distances;  // to the nearest true side, along its normal [m]
  int on_border = 0;
  const Pose3 T_object_world = box.T_world_object.inverse();
  for (int i : pixels) {
    const int u = i % static_cast<int>(cloud->width), v = i / static_cast<int>(cloud->width);
    const int width = static_cast<int>(cloud->width), height = static_cast<int>(cloud->height);
    on_border += u == 0 || v == 0 || u + 1 == width || v + 1 == height;
    const Eigen::Vector3d x = T_object_world * (T_world_camera * (*cloud)[i].getVector3fMap().cast<double>());
    distances.push_back(
        std::min(0.5 * box.dimensions.x() - std::abs(x.x()), 0.5 * box.dimensions.y() - std::abs(x.y())));
  }
  const double median = testing::Median(distances);
  const double worst = *std::max_element(distances.begin(), distances.end());
  std::printf("box top at the hall's pre-grasp pose: %zu inliers, %zu silhouette pixels, inside the true sides by "
              "%.1f mm median, %.1f mm at most\n", top->inliers.size(), pixels.size(), 1000 * median, 1000 * worst);
  EXPECT_GE(pixels.size(), 100u);
  EXPECT_EQ(on_border, 0);
  EXPECT_LT(median, 0.003) << "m: the last pixel before the edge, about 1 mm at 40 cm";
  EXPECT_LT(worst, 0.01) << "m";
}

// The end of the hall's approach, as its scenario 3 runs walk it: the robot maps the box from
// where it starts, walks 1.4 m turning toward it, then the last 35 cm to the pre-grasp pose facing
// it and stands, on odometry that over-reads 10% and drifts 5 cm per metre to the left. Over the
// last stretch the floor, the box top and the north wall fix all but one horizontal direction:
// without silhouettes the pose follows the odometry's error there, with them the box top's
// silhouette fixes it.
TEST(Tracking, NearABoxItsSilhouettesFixWhatThePlanesLeaveFree) {
  const RenderedViews views("configs/scenes/hall.yaml", 4);
  const nav::HumanoidConfig humanoid;
  const nav::Pose2 start{0.0, 0.0, 0.0}, turned{1.41, 0.13, kHallPreGrasp.theta};
  // Frames at 15 Hz: standing 1 s, 1.4 m in 6 s, 35 cm in 3 s, standing 1 s.
  const int look = 15, walk = 90, last = 45, stand = 15;
  const auto between = [](const nav::Pose2& a, const nav::Pose2& b, double s) {
    s = std::clamp(s, 0.0, 1.0);
    return nav::Pose2{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.theta + s * (b.theta - a.theta)};
  };
  const auto base = [&](int k) {
    return k < look + walk ? between(start, turned, static_cast<double>(k - look) / walk)
                           : between(turned, kHallPreGrasp, static_cast<double>(k - look - walk) / last);
  };
  Eigen::Vector2d reading = Eigen::Vector2d::Zero();  // the odometry's position, summed frame by frame
  const auto odometry = [&](int k) {
    if (k > 0) {
      const Eigen::Vector2d step = base(k).Position() - base(k - 1).Position();
      reading += 1.10 * step + 0.05 * Eigen::Vector2d(-step.y(), step.x());
    }
    return nav::NominalCameraPose({reading.x(), reading.y(), base(k).theta}, humanoid);
  };
  double error[2] = {0.0, 0.0};
  int degraded[2] = {0, 0}, with_silhouettes = 0;
  for (int use = 0; use < 2; ++use) {
    TrackingConfig config;
    config.use_silhouettes = use == 1;
    Tracker tracker(config, nav::NominalCameraPose(start, humanoid));
    reading.setZero();
    for (int k = 0; k <= look + walk + last + stand; ++k) {
      const Pose3 truth = nav::NominalCameraPose(base(k), humanoid);
      const TrackResult r = views.Track(tracker, truth, k, k / 15.0, odometry(k));
      degraded[use] += r.status == TrackStatus::kDegraded;
      with_silhouettes += use && r.silhouettes > 0;
      if (k == look + walk + last + stand) {
        error[use] = (r.T_world_camera.translation() - truth.translation()).norm();
      }
    }
  }
  std::printf("1.75 m to the hall's pre-grasp pose on odometry off by 10%% and 5 cm/m: final camera error "
              "%.1f cm without silhouettes (%d degraded frames), %.1f cm with (%d degraded, %d used silhouettes)\n",
              100 * error[0], degraded[0], 100 * error[1], degraded[1], with_silhouettes);
  EXPECT_GE(degraded[0], 10) << "the last stretch has too few planes";
  EXPECT_GT(error[0], 0.015) << "m: without silhouettes the odometry's error shows";
  EXPECT_LT(error[1], 0.005) << "m";
}


// Generated room 48's fault, in the hall: the robot sees the west wall 2 m ahead, looks down at
// the floor and turns 45 deg on it (nothing measures the rotation; the odometry over-reads the turn
// by 6%: 2.7 deg), then looks up at the same wall, now at a slant. Seen from the drifted heading
// the wall lies 2.7 deg and about 9 cm off its landmark: it was mapped a second time there, and the
// copy held the heading off from then on. Now a degraded frame with odometry does not add a plane
// its pose cannot tell from a mapped one: the wall, left out, is matched again by the next frames
// and corrects the heading. The other change of the same commit, the odometry's heading counted as
// less certain after a turn nothing measured (3.4 deg here), does not suffice alone: the floor's
// weight still outvotes the wall's 2.7 deg correction.
TEST(Tracking, AWallSeenAgainAfterATurnOverOpenFloorCorrectsTheHeadingAndIsNotMappedTwice) {
  const RenderedViews views("configs/scenes/hall.yaml", 2);
  const nav::HumanoidConfig humanoid;
  const Eigen::Vector2d at(0.8, 1.0);
  const int frames = 75;
  // Frame k's heading [deg] and how far the camera looks down beyond its nominal 20 deg [deg]:
  // 1 s at the wall, 5 frames to look down, 20 frames turning 45 deg, 5 to look up, 2 s at the wall.
  const auto heading = [](int k) { return 180.0 + 45.0 * std::clamp((k - 20) / 20.0, 0.0, 1.0); };
  const auto down = [](int k) { return 45.0 * std::clamp(std::min(k - 14, 45 - k) / 5.0, 0.0, 1.0); };
  const auto camera = [&](double heading_deg, int k) {
    Pose3 T = nav::NominalCameraPose(nav::Pose2{at.x(), at.y(), heading_deg * M_PI / 180.0}, humanoid);
    T.linear() = T.linear() * Eigen::AngleAxisd(-down(k) * M_PI / 180.0, Eigen::Vector3d::UnitX()).matrix();
    return T;
  };
  const char* names[4] = {"neither", "the heading's growing uncertainty", "no copies while degraded", "both"};
  int west_walls[4] = {0, 0, 0, 0};
  double final_heading_error[4] = {0.0, 0.0, 0.0, 0.0};  // [deg]
  for (int variant = 0; variant < 4; ++variant) {
    TrackingConfig config;
    if (!(variant & 1)) config.odometry_turn_heading_error = config.odometry_walk_heading_error_deg = 0.0;
    if (!(variant & 2)) config.odometry_degraded_adds_only_distinct = false;
    Tracker tracker(config, camera(heading(0), 0));
    for (int k = 0; k < frames; ++k) {
      const Pose3 truth = camera(heading(k), k);
      const Pose3 odometry = camera(180.0 + 1.06 * (heading(k) - 180.0), k);
      const TrackResult r = views.Track(tracker, truth, k, k / 15.0, odometry);
      final_heading_error[variant] = RotationAngle(truth.linear().transpose() * r.T_world_camera.linear()) * 180.0 / M_PI;
      if (std::getenv("PLANEMAP_TRACE")) {
        std::printf("  %s, frame %d: %s, planes %d, matched %d, added %d, heading error %.2f deg; %s\n", names[variant], k,
                    ToString(r.status), r.planes, r.matched, r.added, final_heading_error[variant], r.reason.c_str());
      }
    }
    for (const PlaneLandmark& l : tracker.map().landmarks) {
      west_walls[variant] += l.plane.normal.x() > std::cos(10.0 * M_PI / 180.0);  // the west wall faces +x
    }
    std::printf("the west wall seen again after a 45 deg turn on odometry 2.7 deg off, with %s: %d landmarks of it, "
                "final heading error %.2f deg\n", names[variant], west_walls[variant], final_heading_error[variant]);
  }
  for (int variant = 2; variant < 4; ++variant) {
    EXPECT_EQ(west_walls[variant], 1) << names[variant];
    EXPECT_LT(final_heading_error[variant], 0.5) << "deg, " << names[variant];
  }
}

TEST(Tracking, ARoomCornerSeenNearByAfterItsWallsWereMappedIsNoObject) {
  // The hall's south-west corner. 3 m from it the head camera pans across both walls, mapping each
  // over more than 2 m (room structure); it then walks up to 0.5 m of the corner, where it sees
  // only low pieces of the two walls meeting the floor, as a box's faces meet. The frames take
  // them for an object, from afar too, before the walls are long in the map; the map must hold no
  // object there at the end (in generated rooms such an object stood 1 m out from a corner, in the
  // planner's way to a box beside it).
  const RenderedViews views("configs/scenes/hall.yaml", 3);
  const nav::HumanoidConfig humanoid;
  const Eigen::Vector2d corner(-1.2, -3.0);
  const double toward = std::atan2(-1.0, -1.0);  // [rad]
  const int frames = 130;
  const auto camera = [&](int k) {
    // Frames 0-59: the heading sweeps 40 deg either side of the corner and back; 60-119: the walk.
    const double pan = 40.0 * M_PI / 180.0 * std::sin(2.0 * M_PI * std::min(k, 60) / 60.0);
    const double distance = 3.0 - 2.5 * std::clamp((k - 60) / 60.0, 0.0, 1.0);  // [m]
    const Eigen::Vector2d at = corner - distance * Eigen::Vector2d(std::cos(toward), std::sin(toward));
    return nav::NominalCameraPose(nav::Pose2{at.x(), at.y(), toward + pan}, humanoid);
  };
  const auto near_corner = [&](const Eigen::Vector3d& p) { return (p.head<2>() - corner).norm() < 1.0; };
  const char* names[2] = {"without the map's structure test", "with it"};
  int frame_objects[2] = {0, 0}, map_objects[2] = {0, 0};
  double worst_error[2] = {0.0, 0.0};  // over the walk [m]
  for (int variant = 0; variant < 2; ++variant) {
    TrackingConfig config;
    if (variant == 0) config.structure_min_extent = 1e3;
    Tracker tracker(config, camera(0));
    for (int k = 0; k < frames; ++k) {
      const Pose3 truth = camera(k);
      const auto [cloud, model] = views.View(truth, k);
      for (const FrameObject& o : model.objects) frame_objects[variant] += near_corner(truth * o.center);
      const TrackResult r = tracker.Track(model, *cloud, k / 15.0);
      // Over the walk (while the pan shows one wall and the floor, frames are degraded: the position
      // along the wall is predicted, up to 6 cm off, and found again when the corner is in view).
      if (k >= 60) {
        worst_error[variant] = std::max(worst_error[variant], (r.T_world_camera.translation() - truth.translation()).norm());
      }
      if (std::getenv("PLANEMAP_TRACE")) {
        std::printf("  %s, frame %d: %s, planes %d, matched %d, position error %.2f cm; %s\n", names[variant], k, ToString(r.status),
                    r.planes, r.matched, 100.0 * (r.T_world_camera.translation() - truth.translation()).norm(), r.reason.c_str());
      }
    }
    for (const MapObject& o : tracker.map().objects) map_objects[variant] += !o.structure && near_corner(o.center);
    std::string walls;
    for (const PlaneLandmark& l : tracker.map().landmarks) {
      if (std::abs(l.plane.normal.z()) < 0.5 && l.Extent() > 1.0) walls += " " + std::to_string(l.Extent()).substr(0, 4);
    }
    std::printf("walking up to the hall's corner, %s: %d frame objects at the corner, %d map objects there, "
                "worst position error on the walk %.2f cm; vertical landmarks over 1 m [m]:%s\n", names[variant], frame_objects[variant],
                map_objects[variant], 100.0 * worst_error[variant], walls.c_str());
  }
  EXPECT_GE(frame_objects[1], 5) << "the frames near the corner take the walls for an object: the case this test is for";
  EXPECT_EQ(map_objects[1], 0);
  EXPECT_LT(worst_error[1], 0.02) << "m";
}

}  // namespace
}  // namespace planemap
