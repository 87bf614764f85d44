// The live pipeline as one library call (pipeline/mapper.h): a real sequence and a rendered
// room through planemap::Mapper, against their ground truth; its settings from a config file.
#include <gtest/gtest.h>

#include <fstream>
#include <algorithm>
#include <array>
#include <cmath>
#include <future>

#include "planemap/core/error.h"
#include "planemap/core/trajectory_eval.h"
#include "planemap/io/tum_sequence.h"
#include "planemap/pipeline/mapper.h"
#include "sim_views.h"
#include "test_support.h"

namespace planemap {
namespace {

constexpr double kCm = 100.0;  // [cm/m]

PatternsConfig Patterns() { return LoadPatterns(testing::SourcePath("configs/patterns.yaml")); }
MapperConfig ShippedConfig() { return LoadMapperConfig(testing::SourcePath("configs/default.yaml")); }

// ICL-NUIM office kt0's first 60 frames (2 s); the world is the first camera frame (the first
// frame has no ground-truth pose), so the ATE aligns the trajectories as TUM's tool does.
struct IclRun {
  Trajectory truth, tracked, smoothed;
  FinalMap final_map;
};

IclRun MapIcl(bool two_threads) {
  const CameraIntrinsics camera = LoadCameraIntrinsics(testing::SourcePath("configs/cameras/icl_nuim.yaml"));
  const TumSequence sequence = TumSequence::Open(testing::SharedPath("data/icl_office_kt0"), camera);
  const size_t frames = std::min<size_t>(60, sequence.size());
  IclRun run;
  Mapper mapper(camera, ShippedConfig(), Patterns());
  std::future<Perception> next;
  if (two_threads) next = std::async(std::launch::async, [&] { return mapper.Perceive(sequence.LoadFrame(0)); });
  for (size_t i = 0; i < frames; ++i) {
    const double stamp = sequence.entry(i).depth.stamp;  // the frame's stamp
    MapperStep step;
    if (two_threads) {  // frame i + 1 perceived while frame i is tracked, as `planemap map` does
      const Perception perception = next.get();
      if (i + 1 < frames) next = std::async(std::launch::async, [&, i] { return mapper.Perceive(sequence.LoadFrame(i + 1)); });
      step = mapper.Track(perception, stamp);
    } else {
      step = mapper.Add(sequence.LoadFrame(i));
    }
    if (std::getenv("PLANEMAP_TRACE")) std::printf("frame %zu %s %s\n", i, ToString(step.track.status), step.track.reason.c_str());
    if (sequence.entry(i).T_world_camera) run.truth.push_back({stamp, *sequence.entry(i).T_world_camera});
    run.tracked.push_back({stamp, step.track.T_world_camera});
    run.smoothed.push_back({stamp, step.T_world_camera_smoothed});
  }
  EXPECT_EQ(mapper.frames(TrackStatus::kTracked) + mapper.frames(TrackStatus::kDegraded) + mapper.frames(TrackStatus::kLost),
            static_cast<int>(frames));
  EXPECT_EQ(mapper.frames(TrackStatus::kLost), 0);
  run.final_map = mapper.Finish(/*refine=*/true);
  return run;
}

double AteCm(const Trajectory& truth, const Trajectory& estimate) {
  return kCm * ComputeAte(AssociatePoses(truth, estimate, 0.01)).translation.rmse;
}

TEST(Pipeline, MapsARealSequenceOnOneOrTwoThreadsAlike) {
  PLANEMAP_REQUIRE_SHARED("data/icl_office_kt0");
  const IclRun one = MapIcl(false), two = MapIcl(true);
  ASSERT_EQ(one.tracked.size(), 60u);
  ASSERT_GE(one.truth.size(), 50u);
  const double tracked = AteCm(one.truth, one.tracked), smoothed = AteCm(one.truth, one.smoothed);
  Trajectory refined;
  ASSERT_TRUE(one.final_map.refine.usable) << one.final_map.refine.termination;
  ASSERT_EQ(one.final_map.refined_poses.size(), one.tracked.size());
  for (size_t k = 0; k < one.tracked.size(); ++k) refined.push_back({one.tracked[k].stamp, one.final_map.refined_poses[k]});
  const double refined_ate = AteCm(one.truth, refined);
  std::printf("ICL office kt0, 60 frames: ATE tracked %.2f cm, smoothed %.2f cm, refined %.2f cm; map %zu planes %zu objects\n", tracked,
              smoothed, refined_ate, one.final_map.map.landmarks.size(), one.final_map.map.objects.size());
  // The whole sequence's figures are 0.73 / 0.66 / 0.57 cm (bench_real); its first 2 s no worse.
  EXPECT_LT(tracked, 1.0);
  EXPECT_LT(smoothed, 1.0);
  EXPECT_LT(refined_ate, tracked + 0.1);
  EXPECT_GE(one.final_map.map.landmarks.size(), 4u);
  // The two stages on two threads give the same outputs, pose for pose.
  ASSERT_EQ(two.tracked.size(), one.tracked.size());
  for (size_t k = 0; k < one.tracked.size(); ++k) {
    EXPECT_EQ(one.tracked[k].T_world_camera.matrix(), two.tracked[k].T_world_camera.matrix()) << "frame " << k;
    EXPECT_EQ(one.smoothed[k].T_world_camera.matrix(), two.smoothed[k].T_world_camera.matrix()) << "frame " << k;
  }
}

TEST(Pipeline, WithoutSmoothingTheSmoothedPoseIsTrackings) {
  const Pose3 start = testing::LookAt({0.5, -1.3, 1.0}, {2.5, -0.55, 0.3});
  Mapper mapper(testing::XtionCamera(), ShippedConfig(), Patterns(), start, /*smoothing=*/false);
  for (int k = 0; k < 3; ++k) {
    const Pose3 truth = testing::LookAt({0.5 + 0.05 * k, -1.3, 1.0}, {2.5, -0.55, 0.3});
    RgbdFrame frame = testing::RenderDefaultScene(truth, 10 + k).frame;
    frame.stamp = 0.2 * k;
    const MapperStep step = mapper.Add(frame);
    EXPECT_EQ(step.T_world_camera_smoothed.matrix(), step.track.T_world_camera.matrix());
    EXPECT_EQ(step.window_ms, 0.0);
    EXPECT_EQ(step.track.status, TrackStatus::kTracked) << step.track.reason;
    EXPECT_LT(kCm * (step.track.T_world_camera.translation() - truth.translation()).norm(), 1.0) << "frame " << k;
  }
  EXPECT_EQ(mapper.observations().size(), 3u);
}

TEST(Pipeline, ReadsItsSectionsOfAConfigFileAndNamesABadSetting) {
  // configs/default.yaml holds every tool's sections: the pipeline reads its own.
  const MapperConfig shipped = LoadMapperConfig(testing::SourcePath("configs/default.yaml"));
  const MapperConfig defaults;
  EXPECT_EQ(shipped.backend.window_size, defaults.backend.window_size);
  EXPECT_EQ(shipped.frontend.graph.two_face_min_angle_deg, defaults.frontend.graph.two_face_min_angle_deg);

  const std::string file = ::testing::TempDir() + "pipeline_config.yaml";
  std::ofstream(file) << "render:\n  seed: 3\nbackend:\n  window_size: 7\n";
  EXPECT_EQ(LoadMapperConfig(file).backend.window_size, 7);
  std::ofstream(file) << "frontend:\n  graph:\n    two_face_min_angel_deg: 60\n";
  try {
    LoadMapperConfig(file);
    FAIL() << "a misspelt key was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(file + ":3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("two_face_min_angel_deg"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace planemap

namespace planemap {
namespace {

// A box seen first with two faces (its front and top, the camera in front of it), then with
// three (the camera moving around it to the diagonal between two sides) is one map object
// throughout, and ends with its true size, centre and axes.
TEST(Pipeline, ABoxSeenWithTwoFacesThenThreeIsOneMapObject) {
  const sim::Scene& scene = testing::DefaultScene();
  const sim::SceneObject& box = scene.object("box");
  const sim::Cuboid& cuboid = scene.cuboids[box.cuboids[0]];
  const Eigen::Vector3d centre = box.T_world_object.translation();
  const Eigen::Vector3d x_axis = box.T_world_object.linear().col(0);
  const double front = std::atan2(x_axis.y(), x_axis.x());  // the +x face looks this way
  const int frames = 31;
  auto pose_of = [&](int k) {  // 1.5 m from the centre, 0.6 m high, 1.5 deg further round per frame
    const double bearing = front - (45.0 * M_PI / 180.0) * k / (frames - 1);
    const Eigen::Vector3d eye = centre + Eigen::Vector3d(1.5 * std::cos(bearing), 1.5 * std::sin(bearing), 0.6 - centre.z());
    return testing::LookAt(eye, centre);
  };
  Mapper mapper(testing::XtionCamera(), ShippedConfig(), Patterns(), pose_of(0));
  int two_face_frames = 0, three_face_frames = 0, last_two_face = -1, box_object = -1, mapped_from = -1;
  for (int k = 0; k < frames; ++k) {
    testing::SimFrame sim = testing::RenderDefaultScene(pose_of(k), 700 + k);
    std::array<int, 6> pixels{};
    for (std::uint16_t label : sim.labels.pixels()) {
      for (int f = 0; f < 6; ++f) pixels[f] += label == cuboid.face_labels[f];
    }
    const int shown = static_cast<int>(std::count_if(pixels.begin(), pixels.end(), [](int n) { return n >= 1500; }));
    two_face_frames += shown == 2;
    three_face_frames += shown == 3;
    if (shown == 2) last_two_face = k;
    sim.frame.stamp = 0.2 * k;
    const MapperStep step = mapper.Add(sim.frame);
    EXPECT_EQ(step.track.status, TrackStatus::kTracked) << "frame " << k << ": " << step.track.reason;
    std::vector<int> at_box;
    for (const MapObject& o : mapper.map().objects) {
      if ((o.center - centre).norm() < 0.15) at_box.push_back(o.id);
    }
    EXPECT_LE(at_box.size(), 1u) << "frame " << k << ": the box mapped twice";
    if (at_box.size() == 1 && box_object < 0) {
      box_object = at_box[0];
      mapped_from = k;
    }
    if (box_object >= 0) {
      EXPECT_EQ(at_box, std::vector<int>{box_object}) << "frame " << k;
    }
  }
  std::printf("frames showing the box's two faces: %d (the last: %d), three: %d; the box mapped from frame %d on\n", two_face_frames,
              last_two_face, three_face_frames, mapped_from);
  ASSERT_GE(two_face_frames, 5);
  ASSERT_GE(three_face_frames, 5);
  ASSERT_GE(box_object, 0) << "the box was never mapped";
  EXPECT_LT(mapped_from, last_two_face) << "mapped from its two faces, before a third showed";
  const FinalMap result = mapper.Finish(/*refine=*/false);
  const MapObject* o = nullptr;
  for (const MapObject& m : result.map.objects) {
    if ((m.center - centre).norm() < 0.15) o = &m;
  }
  ASSERT_NE(o, nullptr);
  EXPECT_EQ(o->label, "box");
  EXPECT_GE(o->observations, frames - 5) << "views of two faces and of three went into it";
  std::printf("box: %.1f x %.1f x %.1f cm (complete %d%d%d), centre %.1f mm off, seen %d times\n", 100 * o->dimensions.x(),
              100 * o->dimensions.y(), 100 * o->dimensions.z(), o->dimension_complete[0], o->dimension_complete[1],
              o->dimension_complete[2], 1000 * (o->center - centre).norm(), o->observations);
  EXPECT_LT(kCm * (o->center - centre).norm(), 1.5);
  for (int a = 0; a < 3; ++a) {
    // The true edge this axis runs along.
    int b = 0;
    for (int c = 1; c < 3; ++c) {
      if (std::abs(o->axes.col(a).dot(cuboid.T_world_box.linear().col(c))) > std::abs(o->axes.col(a).dot(cuboid.T_world_box.linear().col(b)))) b = c;
    }
    EXPECT_TRUE(o->dimension_complete[a]) << "axis " << a;
    EXPECT_LT(kCm * std::abs(o->dimensions[a] - cuboid.dimensions[b]), 1.0) << "axis " << a;
    EXPECT_GT(std::abs(o->axes.col(a).dot(cuboid.T_world_box.linear().col(b))), std::cos(2.0 * M_PI / 180.0)) << "axis " << a;
  }
}

}  // namespace
}  // namespace planemap
