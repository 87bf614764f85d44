// The frontend, stage by stage, and the plane segmenters a user would pick instead of ours, on
// the same frames, one thread: rendered frames of the default walk and the shared real data (the
// TUM and ICL sequences, the OSD boxes; frontend_frames.h). Peers: PCL's
// OrganizedMultiPlaneSegmentation and OpenCV's rgbd::RgbdPlane (peer_segmenters.h), and on the
// rendered frames PCL's SAC_MSAC loop (our `msac` reference). Recall where a set has labels.
// Benchmarks are named "Method/set" (Frontend/icl_office_kt0); one table follows the report.
// Run: ./build/bench/bench_frontend [--data DIR] [--benchmark_...] (the table: console output only)
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <omp.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "planemap/core/error.h"
#include "planemap/core/statistics.h"
#include "planemap/frontend/frontend.h"
#include "planemap/frontend/plane_evaluation.h"
#include "planemap/frontend/plane_segmenter.h"
#include "bench_main.h"
#include "frontend_frames.h"
#include "frontend_summary.h"
#include "peer_segmenters.h"

namespace planemap {
namespace {

using Counters = std::map<std::string, double>;

// Counters from an untimed pass over a set's frames, made on a benchmark's first call only
// (Google Benchmark calls it again for each iteration count it tries and for each repetition), so
// the figures do not depend on how many iterations the timing took.
class CountersOnce {
 public:
  void Set(benchmark::State& state, const std::function<Counters()>& compute) {
    if (!counters_) counters_ = compute();
    for (const auto& [name, value] : *counters_) state.counters[name] = value;
  }

 private:
  std::optional<Counters> counters_;
};

// The models the stages start from, each frame's as the stages before left it.
struct Staged {
  FrameModel segmented;    // planes only
  FrameModel intersected;  // and structure, edges
};

// A frame set and the stages' inputs, made on first use.
class SetBench {
 public:
  SetBench(std::unique_ptr<LazyFrameSet> set, PatternsConfig patterns)
      : set_(std::move(set)), patterns_(std::move(patterns)) {}
  const std::string& name() const { return set_->name(); }
  const FrameSet& frames() { return set_->Get(); }
  const PatternsConfig& patterns() const { return patterns_; }
  FrameSetNote Note() const { return {set_->name(), set_->what()}; }

  // The frontend with FrontendConfig{} through the set's camera, and each frame's inputs to
  // Frontend::FindEdges and FindObjects (computed untimed).
  const Frontend& frontend() {
    if (!frontend_) frontend_ = std::make_unique<Frontend>(frames().camera, FrontendConfig{}, patterns_);
    return *frontend_;
  }
  const std::vector<Staged>& staged() {
    if (!staged_) {
      staged_.emplace();
      const std::unique_ptr<PlaneSegmenter> segmenter = MakePlaneSegmenter(FrontendConfig{}.segmentation);
      for (const BenchFrame& f : frames().frames) {
        Staged s;
        s.segmented.planes = segmenter->Segment(*f.cloud).planes;
        s.intersected = s.segmented;
        frontend().FindEdges(*f.cloud, &s.intersected);
        staged_->push_back(std::move(s));
      }
    }
    return *staged_;
  }

 private:
  std::unique_ptr<LazyFrameSet> set_;
  PatternsConfig patterns_;
  std::unique_ptr<Frontend> frontend_;
  std::optional<std::vector<Staged>> staged_;
};

using Segment = std::function<std::vector<DetectedPlane>(const BenchFrame&)>;

// Planes per frame (median) and, on a labelled set, recall and the surfaces evaluated.
Counters SegmenterCounters(const FrameSet& set, const Segment& segment) {
  std::vector<double> planes_per_frame;
  int matched = 0, surfaces = 0;
  for (const BenchFrame& f : set.frames) {
    const std::vector<DetectedPlane> planes = segment(f);
    planes_per_frame.push_back(static_cast<double>(planes.size()));
    if (f.labels.empty()) continue;
    const PlaneEvaluation e = EvaluatePlanes(planes, f.labels, f.valid, f.planes_camera);
    matched += e.matched;
    surfaces += static_cast<int>(e.surfaces.size());
  }
  Counters counters{{"planes_per_frame", Percentile(planes_per_frame, 0.5)}};
  if (set.labelled()) {
    counters["recall"] = surfaces > 0 ? static_cast<double>(matched) / surfaces : 0.0;
    counters["surfaces"] = surfaces;
  }
  return counters;
}

// Times `segment` over the set's frames in turn, then sets the counters.
void RunSegmenter(benchmark::State& state, SetBench& bench, CountersOnce& once, const Segment& segment) {
  const FrameSet& set = bench.frames();
  size_t k = 0;
  for (auto _ : state) {
    std::vector<DetectedPlane> planes = segment(set.frames[k++ % set.frames.size()]);
    benchmark::DoNotOptimize(planes.data());
  }
  once.Set(state, [&] { return SegmenterCounters(set, segment); });
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void RunOurs(benchmark::State& state, SetBench& bench, CountersOnce& once, const SegmenterConfig& config) {
  const std::unique_ptr<PlaneSegmenter> segmenter = MakePlaneSegmenter(config);
  RunSegmenter(state, bench, once, [&](const BenchFrame& f) { return segmenter->Segment(*f.cloud).planes; });
}

// The whole frontend per frame: depth to cloud (a fresh one each time), planes, intersections,
// graph, objects, classes, sizes; from the frame's cloud for a set of clouds (OSD).
void RunFrontend(benchmark::State& state, SetBench& bench, CountersOnce& once, const FrontendConfig& config) {
  const FrameSet& set = bench.frames();
  const Frontend frontend(set.camera, config, bench.patterns());
  auto process = [&](const BenchFrame& f) {
    return set.from_cloud ? frontend.Process(*f.cloud) : frontend.Process(f.rgbd);
  };
  size_t k = 0;
  for (auto _ : state) {
    const FrameModel model = process(set.frames[k++ % set.frames.size()]);
    benchmark::DoNotOptimize(model.objects.data());
  }
  once.Set(state, [&] {
    size_t objects = 0;
    for (const BenchFrame& f : set.frames) objects += process(f).objects.size();
    return Counters{{"objects_per_frame", static_cast<double>(objects) / set.frames.size()}};
  });
}

void RunCloud(benchmark::State& state, SetBench& bench) {
  const FrameSet& set = bench.frames();
  size_t k = 0;
  for (auto _ : state) {
    Cloud::Ptr cloud =
        MakeOrganizedCloud(set.frames[k++ % set.frames.size()].rgbd, set.camera, CloudConfig{});
    benchmark::DoNotOptimize(cloud->points.data());
  }
}

// Times `stage(cloud, &model)` on each frame's model as the stages before left it (copied
// untimed): Frontend::FindEdges (the floor and walls, then the real intersections, eqs. 2-6) and
// Frontend::FindObjects (plane graph, trihedral angles, objects, sizes, centres, grasp sides,
// classes), as Frontend::Process runs them after the planes.
using Stage = std::function<void(const Frontend&, const Cloud&, FrameModel*)>;
void RunStage(benchmark::State& state, SetBench& bench, FrameModel Staged::*input, const Stage& stage) {
  const FrameSet& set = bench.frames();
  const std::vector<Staged>& staged = bench.staged();
  const Frontend& frontend = bench.frontend();
  size_t k = 0;
  for (auto _ : state) {
    const size_t f = k++ % set.frames.size();
    state.PauseTiming();
    FrameModel model = staged[f].*input;
    state.ResumeTiming();
    stage(frontend, *set.frames[f].cloud, &model);
    benchmark::DoNotOptimize(model.planes.data());
  }
}

using Body = std::function<void(benchmark::State&, SetBench&, CountersOnce&)>;
benchmark::internal::Benchmark* Register(const std::string& method, SetBench* bench, Body body) {
  auto once = std::make_shared<CountersOnce>();
  return benchmark::RegisterBenchmark(
             (method + "/" + bench->name()).c_str(),
             [bench, once, body](benchmark::State& state) { body(state, *bench, *once); })
      ->Unit(benchmark::kMillisecond);
}

FrontendConfig Without(const std::function<void(FrontendConfig*)>& change) {
  FrontendConfig config;
  change(&config);
  return config;
}

// Every benchmark on one set; the slow PCL SAC_MSAC (over a second a frame) on rendered frames only.
void RegisterSet(SetBench* bench) {
  auto frontend = [&](const char* method, const FrontendConfig& config) {
    Register(method, bench,
             [config](benchmark::State& s, SetBench& b, CountersOnce& o) { RunFrontend(s, b, o, config); });
  };
  Register("Cloud", bench, [](benchmark::State& s, SetBench& b, CountersOnce&) { RunCloud(s, b); });
  frontend("Frontend", FrontendConfig{});
  // Without the inferences for occluded solids (docs/frontend.md, "Hidden edges"): their cost.
  frontend("FrontendNoOcclusionInference", Without([](FrontendConfig* c) {
             c->intersections.hidden_edges = false;
             c->segmentation.coplanar_max_occluded_gap = 0;
           }));
  frontend("FrontendNoStrips",
           Without([](FrontendConfig* c) { c->segmentation.organized.leftover_hypotheses = 0; }));
  frontend("FrontendNoFringes", Without([](FrontendConfig* c) { c->intersections.fringe_px = 0; }));
  Register("StageIntersections", bench, [](benchmark::State& s, SetBench& b, CountersOnce&) {
    RunStage(s, b, &Staged::segmented,
             [](const Frontend& f, const Cloud& c, FrameModel* m) { f.FindEdges(c, m); });
  });
  Register("StageObjects", bench, [](benchmark::State& s, SetBench& b, CountersOnce&) {
    RunStage(s, b, &Staged::intersected,
             [](const Frontend& f, const Cloud& c, FrameModel* m) { f.FindObjects(c, m); });
  });
  // Within FindObjects: the faces in pieces alone (FindFaces, PlaneGraphConfig::face_piece_*).
  Register("StageFaces", bench, [](benchmark::State& s, SetBench& b, CountersOnce&) {
    const PlaneGraphConfig config = FrontendConfig{}.graph;
    RunStage(s, b, &Staged::intersected,
             [&](const Frontend&, const Cloud& c, FrameModel* m) { FindFaces(c, config, m); });
  });
  Register("Organized", bench,
           [](benchmark::State& s, SetBench& b, CountersOnce& o) { RunOurs(s, b, o, SegmenterConfig{}); });
  // Without the search for thin strips among the pixels no cell's plane took.
  Register("OrganizedNoStrips", bench, [](benchmark::State& s, SetBench& b, CountersOnce& o) {
    SegmenterConfig config;
    config.organized.leftover_hypotheses = 0;
    RunOurs(s, b, o, config);
  });
  Register("PclOrganizedMultiPlane", bench, [](benchmark::State& s, SetBench& b, CountersOnce& o) {
    RunSegmenter(s, b, o, [](const BenchFrame& f) { return PclOrganizedMultiPlanes(f.cloud); });
  });
  Register("OpenCvRgbdPlane", bench, [](benchmark::State& s, SetBench& b, CountersOnce& o) {
    const CameraIntrinsics camera = b.frames().camera;
    RunSegmenter(s, b, o, [&](const BenchFrame& f) { return OpenCvRgbdPlanes(f.rgbd.depth, camera); });
  });
  if (bench->name() == "rendered") {
    Register("PclSacMsac", bench, [](benchmark::State& s, SetBench& b, CountersOnce& o) {
      SegmenterConfig config;
      config.method = "msac";
      RunOurs(s, b, o, config);
    })->MinTime(3.0);
  }
}

// Takes --data DIR (or --data=DIR) out of the arguments: the rest are Google Benchmark's.
std::string TakeDataFolder(int* argc, char** argv) {
  std::string data = PLANEMAP_SOURCE_DIR "/../shared/data";
  int kept = 1;
  for (int i = 1; i < *argc; ++i) {
    if (std::strcmp(argv[i], "--data") == 0 && i + 1 < *argc) {
      data = argv[++i];
    } else if (std::strncmp(argv[i], "--data=", 7) == 0) {
      data = argv[i] + 7;
    } else {
      argv[kept++] = argv[i];
    }
  }
  *argc = kept;
  return data;
}

}  // namespace
}  // namespace planemap

int main(int argc, char** argv) {
  using namespace planemap;
  omp_set_num_threads(1);
#ifdef __GLIBC__
  // Buffers of up to 32 MB come from the heap and stay there once freed. By default glibc serves
  // them by mmap, or not, by a threshold that moves with what was freed before, and returns them
  // to the system: PCL's OrganizedMultiPlaneSegmentation (its integral images, some 30 MB a frame)
  // then took 170-230 ms a frame when it ran after the other benchmarks and 55-65 ms when it ran
  // first, faulting its pages in afresh each frame. The other methods' times do not change.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
  const std::string data = TakeDataFolder(&argc, argv);
  const PatternsConfig patterns = LoadPatterns(PLANEMAP_SOURCE_DIR "/configs/patterns.yaml");
  std::vector<std::unique_ptr<LazyFrameSet>> sets;
  try {
    sets = FindFrameSets(PLANEMAP_SOURCE_DIR, data);
  } catch (const InputError& e) {
    std::fprintf(stderr, "bench_frontend: error: %s\n", e.what());
    return 1;
  }
  std::vector<std::unique_ptr<SetBench>> benches;
  std::vector<FrameSetNote> notes;
  for (std::unique_ptr<LazyFrameSet>& set : sets) {
    benches.push_back(std::make_unique<SetBench>(std::move(set), patterns));
    notes.push_back(benches.back()->Note());
    RegisterSet(benches.back().get());
  }
  const bool console = ReportsToConsole(argc, argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  SummaryReporter reporter(notes);
  if (console) {
    benchmark::RunSpecifiedBenchmarks(&reporter);
    reporter.PrintSummary();
  } else {
    benchmark::RunSpecifiedBenchmarks();
  }
  benchmark::Shutdown();
  return 0;
}
