// Frontend stages on 640x480 frames of the default scene (full noise model), and on the same
// frames the peers a user would pick instead of our organized segmenter: PCL's SAC_MSAC loop (our
// `msac` reference), PCL's OrganizedMultiPlaneSegmentation (with integral-image normals) and
// OpenCV's rgbd::RgbdPlane. Recall = labelled surfaces (>= 1000 valid pixels) matched by a plane
// with IoU >= 0.5. Also the whole frontend per frame. One thread.
// Run: ./build/bench/bench_frontend [--benchmark_format=json] (the summary table: console output only)
#include <cstdio>
#include <map>

#include <benchmark/benchmark.h>
#include <omp.h>
#include <opencv2/rgbd.hpp>
#include <pcl/features/integral_image_normal.h>
#include <pcl/segmentation/organized_multi_plane_segmentation.h>

#include "planemap/frontend/frontend.h"
#include "planemap/frontend/organized_cloud.h"
#include "planemap/frontend/plane_evaluation.h"
#include "planemap/frontend/plane_segmenter.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/virtual_camera.h"
#include "planemap/sim/walk.h"
#include "bench_main.h"

namespace planemap {
namespace {

std::string Config(const std::string& relative) { return std::string(PLANEMAP_SOURCE_DIR) + "/configs/" + relative; }

struct Frame {
  RgbdFrame rgbd;
  LabelImage labels;
  std::map<std::uint16_t, Plane> planes_camera;
  Cloud::Ptr cloud;
  std::vector<bool> valid;
};

// 12 frames along the default walk toward the box.
struct Frames {
  CameraIntrinsics camera = LoadCameraIntrinsics(Config("cameras/xtion_nao.yaml"));
  std::vector<Frame> frames;
  Frames() {
    const sim::Scene scene = sim::LoadScene(Config("scenes/default.yaml"));
    const sim::VirtualCamera virtual_camera(scene, camera, sim::RenderConfig{});
    const Trajectory walk = sim::LoadTrajectory(Config("walks/default.yaml"));
    for (size_t k = 0; k < 12; ++k) {
      const Pose3& T = walk[k * (walk.size() - 1) / 11].T_world_camera;
      sim::RenderedFrame r = virtual_camera.Render(T, virtual_camera.FrameSeed(static_cast<int>(k)));
      Frame f;
      f.rgbd.depth = std::move(r.depth);
      f.rgbd.color = std::move(r.color);
      f.labels = std::move(r.labels);
      for (const sim::Surface& s : scene.surfaces) f.planes_camera[s.label] = TransformPlane(T.inverse(), s.plane_world);
      f.cloud = MakeOrganizedCloud(f.rgbd, camera, CloudConfig{});
      f.valid.resize(f.cloud->size());
      for (size_t i = 0; i < f.cloud->size(); ++i) f.valid[i] = IsValidPoint((*f.cloud)[i]);
      frames.push_back(std::move(f));
    }
  }
};

const Frames& Shared() {
  static const Frames frames;
  return frames;
}

// Runs `segment` (frame -> planes) over all frames, timed, then sets the recall counter.
template <typename Segment>
void RunSegmenter(benchmark::State& state, Segment segment) {
  const Frames& data = Shared();
  size_t k = 0;
  for (auto _ : state) {
    std::vector<DetectedPlane> planes = segment(data.frames[k % data.frames.size()]);
    benchmark::DoNotOptimize(planes.data());
    ++k;
  }
  int matched = 0, surfaces = 0;
  for (const Frame& f : data.frames) {
    const PlaneEvaluation e = EvaluatePlanes(segment(f), f.labels, f.valid, f.planes_camera);
    matched += e.matched;
    surfaces += static_cast<int>(e.surfaces.size());
  }
  state.counters["recall"] = static_cast<double>(matched) / surfaces;
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_Cloud(benchmark::State& state) {
  const Frames& data = Shared();
  size_t k = 0;
  for (auto _ : state) {
    Cloud::Ptr cloud = MakeOrganizedCloud(data.frames[k++ % data.frames.size()].rgbd, data.camera, CloudConfig{});
    benchmark::DoNotOptimize(cloud->points.data());
  }
}

void BM_Organized(benchmark::State& state) {
  const auto segmenter = MakePlaneSegmenter(SegmenterConfig{});
  RunSegmenter(state, [&](const Frame& f) { return segmenter->Segment(*f.cloud).planes; });
}

// Without the search for thin strips among the pixels no cell's plane took.
void BM_OrganizedNoStrips(benchmark::State& state) {
  SegmenterConfig config;
  config.organized.leftover_hypotheses = 0;
  const auto segmenter = MakePlaneSegmenter(config);
  RunSegmenter(state, [&](const Frame& f) { return segmenter->Segment(*f.cloud).planes; });
}

void BM_PclSacMsac(benchmark::State& state) {
  SegmenterConfig config;
  config.method = "msac";
  const auto segmenter = MakePlaneSegmenter(config);
  RunSegmenter(state, [&](const Frame& f) { return segmenter->Segment(*f.cloud).planes; });
}

// PCL's organized multi-plane segmentation. Settings: the best recall of angular thresholds
// 2-10 deg, distance thresholds 2 and 5 cm and normal smoothing 10 and 20 tried on these frames.
void BM_PclOrganizedMultiPlane(benchmark::State& state) {
  RunSegmenter(state, [&](const Frame& f) {
    pcl::IntegralImageNormalEstimation<pcl::PointXYZRGB, pcl::Normal> ne;
    ne.setNormalEstimationMethod(ne.COVARIANCE_MATRIX);
    ne.setMaxDepthChangeFactor(0.02f);
    ne.setNormalSmoothingSize(10.0f);
    ne.setInputCloud(f.cloud);
    auto normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
    ne.compute(*normals);
    pcl::OrganizedMultiPlaneSegmentation<pcl::PointXYZRGB, pcl::Normal, pcl::Label> mps;
    mps.setMinInliers(400);
    mps.setAngularThreshold(6.0 * M_PI / 180.0);
    mps.setDistanceThreshold(0.05);
    mps.setInputNormals(normals);
    mps.setInputCloud(f.cloud);
    std::vector<pcl::PlanarRegion<pcl::PointXYZRGB>, Eigen::aligned_allocator<pcl::PlanarRegion<pcl::PointXYZRGB>>> regions;
    std::vector<pcl::ModelCoefficients> coefficients;
    std::vector<pcl::PointIndices> inliers;
    mps.segment(coefficients, inliers);
    std::vector<DetectedPlane> planes;
    for (size_t i = 0; i < inliers.size(); ++i) {
      DetectedPlane p;
      p.id = static_cast<int>(i);
      const auto& c = coefficients[i].values;
      p.plane = {Eigen::Vector3d(c[0], c[1], c[2]), c[3]};
      p.inliers.assign(inliers[i].indices.begin(), inliers[i].indices.end());
      planes.push_back(std::move(p));
    }
    return planes;
  });
}

// OpenCV's RgbdPlane (block-wise MSE growing), with its Kinect sensor error model.
void BM_OpenCvRgbdPlane(benchmark::State& state) {
  const Frames& data = Shared();
  const cv::Matx33d K(data.camera.fx, 0, data.camera.cx, 0, data.camera.fy, data.camera.cy, 0, 0, 1);
  RunSegmenter(state, [&](const Frame& f) {
    cv::Mat depth(f.rgbd.depth.height(), f.rgbd.depth.width(), CV_32FC1, const_cast<float*>(f.rgbd.depth.data()));
    cv::Mat points;
    cv::rgbd::depthTo3d(depth, K, points);
    cv::rgbd::RgbdPlane plane_finder(cv::rgbd::RgbdPlane::RGBD_PLANE_METHOD_DEFAULT, 40, 400, 0.02, 0.0075, 0, 0);
    cv::Mat mask, coefficients;
    plane_finder(points, mask, coefficients);
    std::vector<DetectedPlane> planes(coefficients.rows);
    for (int i = 0; i < coefficients.rows; ++i) {
      const cv::Vec4f c = coefficients.at<cv::Vec4f>(i);
      planes[i].id = i;
      planes[i].plane = {Eigen::Vector3d(c[0], c[1], c[2]), c[3]};
    }
    for (int v = 0; v < mask.rows; ++v) {
      for (int u = 0; u < mask.cols; ++u) {
        const int label = mask.at<std::uint8_t>(v, u);
        if (label < coefficients.rows) planes[label].inliers.push_back(v * mask.cols + u);
      }
    }
    return planes;
  });
}

// The whole frontend: depth to cloud, planes, intersections, graph, objects, classes, sizes.
void RunFrontend(benchmark::State& state, const FrontendConfig& config) {
  const Frames& data = Shared();
  const Frontend frontend(data.camera, config, LoadPatterns(Config("patterns.yaml")));
  size_t k = 0;
  for (auto _ : state) {
    const FrameModel model = frontend.Process(data.frames[k++ % data.frames.size()].rgbd);
    benchmark::DoNotOptimize(model.objects.data());
  }
  // Counted over one pass of every frame, untimed, so the figure does not depend on how many
  // iterations the timing took.
  size_t objects = 0;
  for (const Frame& f : data.frames) objects += frontend.Process(f.rgbd).objects.size();
  state.counters["objects_per_frame"] = static_cast<double>(objects) / data.frames.size();
}
void BM_Frontend(benchmark::State& state) { RunFrontend(state, FrontendConfig{}); }
// The same without the inferences for occluded solids (docs/frontend.md, "Hidden edges"): their cost.
void BM_FrontendNoOcclusionInference(benchmark::State& state) {
  FrontendConfig config;
  config.intersections.hidden_edges = false;
  config.segmentation.coplanar_max_occluded_gap = 0;
  RunFrontend(state, config);
}

// Stage by stage, each on the output of the stages before it (computed untimed):
// Frontend::FindEdges (the floor and walls, then the real intersections, eqs. 2-6) and
// Frontend::FindObjects (plane graph, trihedral angles, objects, sizes, centres, grasp sides,
// classes), as Frontend::Process runs them after the planes.
struct Staged {
  FrameModel segmented;    // planes only
  FrameModel intersected;  // and structure, edges
};
struct Stages {
  Frontend frontend{Shared().camera, FrontendConfig{}, LoadPatterns(Config("patterns.yaml"))};
  std::vector<Staged> frames;
  Stages() {
    const std::unique_ptr<PlaneSegmenter> segmenter = MakePlaneSegmenter(FrontendConfig{}.segmentation);
    for (const Frame& f : Shared().frames) {
      Staged s;
      s.segmented.planes = segmenter->Segment(*f.cloud).planes;
      s.intersected = s.segmented;
      frontend.FindEdges(*f.cloud, &s.intersected);
      frames.push_back(std::move(s));
    }
  }
};
const Stages& SharedStages() {
  static const Stages stages;
  return stages;
}

// Times `stage(cloud, &model)` on each frame's model as the stages before left it (copied
// untimed).
template <typename Stage>
void RunStage(benchmark::State& state, FrameModel Staged::*input, Stage stage) {
  const Frames& data = Shared();
  const Stages& stages = SharedStages();
  size_t k = 0;
  for (auto _ : state) {
    const size_t f = k++ % data.frames.size();
    state.PauseTiming();
    FrameModel model = stages.frames[f].*input;
    state.ResumeTiming();
    stage(*data.frames[f].cloud, &model);
    benchmark::DoNotOptimize(model.planes.data());
  }
}
void BM_StageIntersections(benchmark::State& state) {
  RunStage(state, &Staged::segmented, [](const Cloud& cloud, FrameModel* model) { SharedStages().frontend.FindEdges(cloud, model); });
}
void BM_StageObjects(benchmark::State& state) {
  RunStage(state, &Staged::intersected, [](const Cloud& cloud, FrameModel* model) { SharedStages().frontend.FindObjects(cloud, model); });
}
// Within FindObjects: the faces in pieces alone (FindFaces, PlaneGraphConfig::face_piece_*).
void BM_StageFaces(benchmark::State& state) {
  const PlaneGraphConfig config = FrontendConfig{}.graph;
  RunStage(state, &Staged::intersected, [&](const Cloud& cloud, FrameModel* model) { FindFaces(cloud, config, model); });
}

// Without the segmenter's search for thin strips (organized.leftover_hypotheses: 0).
void BM_FrontendNoStrips(benchmark::State& state) {
  FrontendConfig config;
  config.segmentation.organized.leftover_hypotheses = 0;
  RunFrontend(state, config);
}

// Without the planes' fringes in the intersections (intersections.fringe_px: 0).
void BM_FrontendNoFringes(benchmark::State& state) {
  FrontendConfig config;
  config.intersections.fringe_px = 0;
  RunFrontend(state, config);
}

BENCHMARK(BM_Cloud)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Frontend)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrontendNoOcclusionInference)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrontendNoStrips)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrontendNoFringes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StageIntersections)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StageObjects)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StageFaces)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Organized)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OrganizedNoStrips)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PclOrganizedMultiPlane)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OpenCvRgbdPlane)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PclSacMsac)->Unit(benchmark::kMillisecond)->MinTime(3.0);

class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      // With --benchmark_repetitions, the table shows each method's median (the repetitions
      // and the other aggregates are in the report above).
      if (run.run_type == Run::RT_Aggregate && run.aggregate_name != "median") continue;
      if (run.run_type == Run::RT_Iteration && run.repetitions > 1) continue;
      const std::string name = run.run_name.function_name;
      ms_[name] = run.GetAdjustedRealTime();
      if (run.counters.count("recall")) recall_[name] = run.counters.at("recall").value;
    }
  }
  void PrintSummary() const {
    // Each part needs the benchmarks it compares (--benchmark_filter may leave some out).
    std::printf("\n");
    if (ms_.count("BM_Organized")) {
      std::printf("Plane segmentation of 640x480 frames, one thread (times relative to our organized segmenter):\n");
      std::printf("  %-28s %9s %12s %8s\n", "", "ms/frame", "x organized", "recall");
      for (const auto& [name, recall] : recall_) {
        std::printf("  %-28s %9.2f %11.1fx %8.3f\n", name.c_str(), ms_.at(name), ms_.at(name) / ms_.at("BM_Organized"), recall);
      }
    }
    if (!ms_.count("BM_Cloud") || !ms_.count("BM_Frontend")) return;
    std::printf("  depth to cloud: %.2f ms/frame; "
                "whole frontend (depth image to classified objects): %.2f ms/frame\n",
                ms_.at("BM_Cloud"), ms_.at("BM_Frontend"));
    if (ms_.count("BM_Organized") && ms_.count("BM_StageIntersections") && ms_.count("BM_StageObjects")) {
      std::printf("  by stage, each timed on its own: cloud %.2f, planes %.2f, floor/walls and intersections %.2f, "
                  "graph, objects, sizes and classes %.2f ms/frame\n",
                  ms_.at("BM_Cloud"), ms_.at("BM_Organized"), ms_.at("BM_StageIntersections"), ms_.at("BM_StageObjects"));
    }
    if (ms_.count("BM_FrontendNoOcclusionInference")) {
      std::printf("  without the occlusion inferences (hidden edges, occluded merge): %.2f ms/frame (%.2fx)\n",
                  ms_.at("BM_FrontendNoOcclusionInference"), ms_.at("BM_Frontend") / ms_.at("BM_FrontendNoOcclusionInference"));
    }
    if (ms_.count("BM_FrontendNoStrips")) {
      std::printf("  without the search for thin strips: %.2f ms/frame (%.2fx)\n", ms_.at("BM_FrontendNoStrips"),
                  ms_.at("BM_Frontend") / ms_.at("BM_FrontendNoStrips"));
    }
    if (ms_.count("BM_FrontendNoFringes")) {
      std::printf("  without the planes' fringes in the intersections: %.2f ms/frame (%.2fx)\n", ms_.at("BM_FrontendNoFringes"),
                  ms_.at("BM_Frontend") / ms_.at("BM_FrontendNoFringes"));
    }
  }

 private:
  std::map<std::string, double> ms_, recall_;
};

}  // namespace
}  // namespace planemap

int main(int argc, char** argv) {
  omp_set_num_threads(1);
  const bool console = planemap::ReportsToConsole(argc, argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  planemap::SummaryReporter reporter;
  if (console) {
    benchmark::RunSpecifiedBenchmarks(&reporter);
    reporter.PrintSummary();
  } else {
    benchmark::RunSpecifiedBenchmarks();
  }
  benchmark::Shutdown();
  return 0;
}
