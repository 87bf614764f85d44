// Tracking time per frame at 640x480, median and 95th percentile, with the ATE beside it, on
// 100 frames of the rendered default walk of tests/test_tracking.cpp (Nao-like, 5 Hz, full sensor
// noise, seed 11): the end of the straight stretch past the furniture, the turn on the spot and
// the approach to the box. Every method starts at the window's true first pose. Side by side:
//   - our Tracker::Track (frame to map), default config (refine "points"), and refine "icp";
//   - the peers a user would pick for pose tracking from depth alone: PCL's point-to-plane ICP
//     (IterativeClosestPointWithNormals, through our RefineIcp) and PCL's GICP, frame to frame on
//     the cloud voxel-downsampled at 2 cm, each started at the previous frame's pose;
//   - the frontend (cloud -> frame model) our tracker runs after, for context.
// Times are per frame from the organized cloud on: ours exclude the frontend (the table adds it
// back in a row of its own); the peers' include their downsampling, normals or covariances.
// Each method runs the window once (tracking is sequential): its frames are the samples.
// One thread. Run: ./build/bench/bench_tracking [--benchmark_format=json]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <omp.h>
#include <pcl/common/io.h>
#include <pcl/features/normal_3d.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/registration/gicp.h>

#include "planemap/core/statistics.h"
#include "planemap/core/trajectory_eval.h"
#include "planemap/frontend/frontend.h"
#include "planemap/frontend/plane_registration.h"
#include "planemap/frontend/tracker.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/virtual_camera.h"
#include "planemap/sim/walk.h"
#include "bench_main.h"

namespace planemap {
namespace {

std::string Config(const std::string& relative) { return std::string(PLANEMAP_SOURCE_DIR) + "/configs/" + relative; }

// Frames [90, 190) of the walk's 190 (45 straight ahead, 15 turning 84 deg on the spot, 38
// approaching the box, 2 standing): the whole walk would take the PCL peers some 4 minutes.
constexpr size_t kFirstFrame = 90;
constexpr size_t kFrames = 100;

// The rendered window of the walk, with each frame's model from our frontend (untimed).
struct Sequence {
  CameraIntrinsics camera = LoadCameraIntrinsics(Config("cameras/xtion_nao.yaml"));
  Frontend frontend{camera, FrontendConfig{}, LoadPatterns(Config("patterns.yaml"))};
  Trajectory truth;
  std::vector<RgbdFrame> frames;
  std::vector<FrameModel> models;

  Sequence() {
    sim::WalkConfig walk;
    walk.waypoints = {-0.7, -1.3, 1.95, -1.3, 2.03, -0.546};
    walk.rate = 5.0;
    const Trajectory whole = sim::GenerateWalk(walk);
    truth.assign(whole.begin() + kFirstFrame, whole.begin() + std::min(whole.size(), kFirstFrame + kFrames));
    sim::RenderConfig render;
    render.seed = 11;
    const sim::VirtualCamera virtual_camera(sim::LoadScene(Config("scenes/default.yaml")), camera, render);
    for (size_t k = 0; k < truth.size(); ++k) {
      const int index = static_cast<int>(kFirstFrame + k);  // the walk's frame, noise seeded as in the test
      sim::RenderedFrame r = virtual_camera.Render(truth[k].T_world_camera, virtual_camera.FrameSeed(index));
      RgbdFrame f;
      f.index = index;
      f.stamp = truth[k].stamp;
      f.depth = std::move(r.depth);
      f.color = std::move(r.color);
      models.push_back(frontend.Process(*MakeCloud(f)));
      frames.push_back(std::move(f));
    }
  }
  // Rebuilt per use rather than kept: 10 MB a frame.
  Cloud::Ptr MakeCloud(const RgbdFrame& frame) const { return MakeOrganizedCloud(frame, camera, CloudConfig{}); }
};

const Sequence& Shared() {
  static const Sequence sequence;
  return sequence;
}

// Frame k's organized cloud -> its T_world_camera (nothing for a step that estimates no pose).
// A fresh step is made for every run of the sequence, so state does not leak between runs.
using Step = std::function<std::optional<Pose3>(size_t k, const Cloud::ConstPtr& cloud)>;

// Per-frame times and accuracy of each method, for the table printed after the run.
struct MethodResult {
  std::vector<double> ms;  // per frame, in order
  std::optional<double> ate_mm;
};
std::map<std::string, MethodResult>& Results() {
  static std::map<std::string, MethodResult> results;
  return results;
}

// Runs the sequence through a fresh step per benchmark iteration, timing each frame's step alone
// (the cloud is built outside the clock); counters: per-frame median and p95, ATE RMSE.
void RunSequence(benchmark::State& state, const std::string& name, const std::function<Step()>& make_step) {
  using Clock = std::chrono::steady_clock;
  const Sequence& data = Shared();
  MethodResult result;
  Trajectory estimate;
  for (auto _ : state) {
    const Step step = make_step();
    result.ms.clear();
    estimate.clear();
    double seconds = 0.0;
    for (size_t k = 0; k < data.frames.size(); ++k) {
      const Cloud::ConstPtr cloud = data.MakeCloud(data.frames[k]);
      const Clock::time_point start = Clock::now();
      const std::optional<Pose3> T_world_camera = step(k, cloud);
      const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
      seconds += elapsed;
      result.ms.push_back(1000.0 * elapsed);
      if (T_world_camera) estimate.push_back({data.truth[k].stamp, *T_world_camera});
    }
    state.SetIterationTime(seconds);
  }
  state.counters["frames"] = static_cast<double>(result.ms.size());
  state.counters["median_ms"] = Percentile(result.ms, 0.5);
  state.counters["p95_ms"] = Percentile(result.ms, 0.95);
  if (!estimate.empty()) {
    const TrajectoryEvaluation e = EvaluateTrajectory(data.truth, estimate, EvalConfig{}, "truth", name);
    result.ate_mm = 1000.0 * e.ate.translation.rmse;
    state.counters["ate_mm"] = *result.ate_mm;
  }
  Results()[name] = std::move(result);
}

// Our tracker: frame-to-map, on the precomputed frame models.
void RunTracker(benchmark::State& state, const std::string& name, const std::string& refine) {
  const Sequence& data = Shared();
  TrackingConfig config;
  config.refine = refine;
  RunSequence(state, name, [&] {
    auto tracker = std::make_shared<Tracker>(config, data.truth.front().T_world_camera);
    return [tracker, &data](size_t k, const Cloud::ConstPtr& cloud) -> std::optional<Pose3> {
      return tracker->Track(data.models[k], *cloud, data.truth[k].stamp).T_world_camera;
    };
  });
}

// The peers' settings. Their input: the cloud's valid points up to the depth our tracker uses
// planes to (4 m: beyond it the depth steps are 5+ cm and pull frame-to-frame registration toward
// no motion; on the whole range their ATE is 3x worse), one per 2 cm voxel (the centroid).
// Correspondences within 10 cm: the lowest ATE for both of 5, 10 and 20 cm tried here.
constexpr double kPeerVoxel = 0.02;  // [m]
const double kPeerMaxDepth = TrackingConfig{}.max_depth;
IcpConfig PeerConfig() {
  IcpConfig config;
  config.voxel_size = 0.0;  // downsampled already (before the normals)
  config.max_correspondence_distance = 0.10;
  config.max_iterations = 30;
  return config;
}

pcl::PointCloud<pcl::PointXYZ>::Ptr Downsample(const Cloud::ConstPtr& cloud) {
  pcl::VoxelGrid<pcl::PointXYZRGB> grid;  // skips NaN points of the organized cloud
  grid.setInputCloud(cloud);
  grid.setLeafSize(kPeerVoxel, kPeerVoxel, kPeerVoxel);
  grid.setFilterFieldName("z");
  grid.setFilterLimits(0.0f, static_cast<float>(kPeerMaxDepth));
  Cloud downsampled;
  grid.filter(downsampled);
  auto points = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  pcl::copyPointCloud(downsampled, *points);
  return points;
}

// Chains frame-to-frame registrations into world poses, starting at the true first pose.
// `register_frame` aligns frame k's cloud to the previous one it kept, returning T_previous_current.
Step FrameToFrame(const std::function<Pose3(const Cloud::ConstPtr& cloud, bool first)>& register_frame) {
  const Pose3 T_world_first = Shared().truth.front().T_world_camera;
  auto T_world_camera = std::make_shared<Pose3>(T_world_first);
  return [T_world_camera, register_frame](size_t k, const Cloud::ConstPtr& cloud) -> std::optional<Pose3> {
    const Pose3 T_previous_current = register_frame(cloud, k == 0);
    *T_world_camera = *T_world_camera * T_previous_current;
    return *T_world_camera;
  };
}

// PCL point-to-plane ICP (our RefineIcp wraps pcl::IterativeClosestPointWithNormals), normals from
// 5 cm neighbourhoods of the downsampled cloud, oriented to the camera.
void BM_PclIcpPointToPlane(benchmark::State& state) {
  const IcpConfig icp = PeerConfig();
  RunSequence(state, "PCL ICP point-to-plane", [icp] {
    auto previous = std::make_shared<pcl::PointCloud<pcl::PointNormal>::Ptr>();
    return FrameToFrame([icp, previous](const Cloud::ConstPtr& cloud, bool first) {
      const pcl::PointCloud<pcl::PointXYZ>::Ptr points = Downsample(cloud);
      pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
      estimation.setInputCloud(points);
      estimation.setSearchMethod(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
      estimation.setRadiusSearch(0.05);
      pcl::PointCloud<pcl::Normal> normals;
      estimation.compute(normals);
      auto current = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
      pcl::concatenateFields(*points, normals, *current);
      const Pose3 T = first ? Pose3::Identity() : RefineIcp(*current, **previous, Pose3::Identity(), icp).T_target_source;
      *previous = current;
      return T;
    });
  });
}

// GICP keeps each cloud's covariances for the next frame, where it is the target: every frame's
// are computed once, as a frame-to-frame user would (PCL has no getter for the source's).
class Gicp : public pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> {
 public:
  MatricesVectorPtr SourceCovariances() const { return input_covariances_; }
};

// PCL GICP (covariances of 20 neighbours, PCL's default).
void BM_PclGicp(benchmark::State& state) {
  const IcpConfig config = PeerConfig();
  RunSequence(state, "PCL GICP", [config] {
    struct Previous {
      pcl::PointCloud<pcl::PointXYZ>::Ptr points;
      Gicp::MatricesVectorPtr covariances;
    };
    auto previous = std::make_shared<Previous>();
    return FrameToFrame([config, previous](const Cloud::ConstPtr& cloud, bool first) {
      const pcl::PointCloud<pcl::PointXYZ>::Ptr points = Downsample(cloud);
      Pose3 T = Pose3::Identity();
      Gicp::MatricesVectorPtr covariances;
      if (!first) {
        Gicp gicp;
        gicp.setMaxCorrespondenceDistance(config.max_correspondence_distance);
        gicp.setMaximumIterations(config.max_iterations);
        gicp.setTransformationEpsilon(config.transformation_epsilon);
        gicp.setInputSource(points);
        gicp.setInputTarget(previous->points);
        gicp.setTargetCovariances(previous->covariances);  // after setInputTarget, which clears them
        pcl::PointCloud<pcl::PointXYZ> aligned;
        gicp.align(aligned);
        T.matrix() = gicp.getFinalTransformation().cast<double>();
        T.linear() = Eigen::Quaterniond(T.rotation()).normalized().toRotationMatrix();  // float drift
        covariances = gicp.SourceCovariances();
      }
      previous->points = points;
      previous->covariances = covariances;  // empty for the first frame: GICP computes them
      return T;
    });
  });
}

void BM_Frontend(benchmark::State& state) {
  const Sequence& data = Shared();
  RunSequence(state, "frontend", [&data] {
    return [&data](size_t, const Cloud::ConstPtr& cloud) -> std::optional<Pose3> {
      const FrameModel model = data.frontend.Process(*cloud);
      benchmark::DoNotOptimize(model.objects.data());
      return std::nullopt;
    };
  });
}

void BM_TrackerPoints(benchmark::State& state) { RunTracker(state, "planemap (refine points)", "points"); }
void BM_TrackerIcp(benchmark::State& state) { RunTracker(state, "planemap (refine icp)", "icp"); }

// One run of the sequence each: its frames are the samples.
BENCHMARK(BM_Frontend)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_TrackerPoints)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_TrackerIcp)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_PclIcpPointToPlane)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_PclGicp)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);

// The methods side by side, times relative to our default tracker's median.
void PrintSummary() {
  const auto& results = Results();
  const auto reference = results.find("planemap (refine points)");
  if (reference == results.end()) return;
  const double reference_ms = Percentile(reference->second.ms, 0.5);
  std::printf("\nTracking %zu frames of 640x480 (default walk: straight, turn, approach; 5 Hz, full noise), one thread; ms per frame:\n",
              reference->second.ms.size());
  std::printf("  %-36s %8s %8s %9s %8s\n", "", "median", "p95", "x ours", "ATE mm");
  auto row = [&](const std::string& name, const std::vector<double>& ms, std::optional<double> ate_mm) {
    const double median = Percentile(ms, 0.5);
    std::printf("  %-36s %8.2f %8.2f %8.1fx", name.c_str(), median, Percentile(ms, 0.95), median / reference_ms);
    if (ate_mm) std::printf(" %8.1f", *ate_mm);
    std::printf("\n");
  };
  for (const char* name : {"planemap (refine points)", "planemap (refine icp)", "PCL ICP point-to-plane", "PCL GICP"}) {
    if (results.count(name)) row(name, results.at(name).ms, results.at(name).ate_mm);
  }
  if (const auto frontend = results.find("frontend"); frontend != results.end()) {
    row("frontend (cloud -> frame model)", frontend->second.ms, std::nullopt);
    std::vector<double> total = frontend->second.ms;  // the same frames, in order
    for (size_t k = 0; k < total.size(); ++k) total[k] += reference->second.ms[k];
    row("frontend + planemap (refine points)", total, reference->second.ate_mm);
  }
  std::printf("  (ours: frame to map, after the frontend; PCL: frame to frame on the %.0f cm voxel cloud up to %.0f m, "
              "times including downsampling, normals / covariances)\n", 100 * kPeerVoxel, kPeerMaxDepth);
}

}  // namespace
}  // namespace planemap

int main(int argc, char** argv) {
  omp_set_num_threads(1);
  return planemap::RunBenchmarksThenSummary(argc, argv, planemap::PrintSummary);
}
