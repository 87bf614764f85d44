// Rendered 640x480 frames per second of the virtual RGB-D camera: exact ray casting alone, the
// full sensor noise model on top, and motion blur (5 renders per frame), side by side with the
// 30 Hz of the sensor it stands in for. Run: ./build/bench/bench_render
#include <cstdio>
#include <map>
#include <string>

#include <benchmark/benchmark.h>
#include <omp.h>

#include "planemap/core/intrinsics.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/virtual_camera.h"
#include "planemap/sim/walk.h"

namespace planemap::sim {
namespace {

std::string Config(const std::string& relative) { return std::string(PLANEMAP_SOURCE_DIR) + "/configs/" + relative; }

struct Fixture {
  Scene scene = LoadScene(Config("scenes/default.yaml"));
  CameraIntrinsics camera = LoadCameraIntrinsics(Config("cameras/xtion_nao.yaml"));
  Trajectory walk = LoadTrajectory(Config("walks/default.yaml"));
};

const Fixture& Shared() {
  static const Fixture fixture;
  return fixture;
}

void RunRender(benchmark::State& state, const RenderConfig& config, bool blur) {
  const Fixture& f = Shared();
  const VirtualCamera camera(f.scene, f.camera, config);
  size_t k = 0;
  for (auto _ : state) {
    // Walk along the default approach so the benchmark sees the views a run sees.
    const size_t i = (k * 7) % f.walk.size();
    const std::optional<Pose3> start = blur ? std::optional<Pose3>(f.walk[i > 0 ? i - 1 : 0].T_world_camera) : std::nullopt;
    RenderedFrame frame = camera.Render(f.walk[i].T_world_camera, camera.FrameSeed(static_cast<int>(k)), start);
    benchmark::DoNotOptimize(frame.depth.data());
    ++k;
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_RenderExact(benchmark::State& state) {
  RenderConfig config;
  config.add_noise = false;
  RunRender(state, config, false);
}

void BM_RenderFullNoise(benchmark::State& state) { RunRender(state, RenderConfig{}, false); }

void BM_RenderFullNoiseMotionBlur(benchmark::State& state) {
  RenderConfig config;
  config.noise.motion_blur = true;
  RunRender(state, config, true);
}

BENCHMARK(BM_RenderExact)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_RenderFullNoise)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_RenderFullNoiseMotionBlur)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

// Keeps every run's frames per second to print the comparison once all have run.
class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) fps_[run.benchmark_name()] = run.counters.at("fps").value;
  }
  void PrintSummary() const {
    // The comparison needs the exact renderer's run; a --benchmark_filter that leaves it (or every
    // run) out gets the console lines above and no summary.
    const auto exact_run = fps_.find("BM_RenderExact/min_time:2.000/real_time");
    if (exact_run == fps_.end()) return;
    const double exact = exact_run->second;
    std::printf("\n640x480 frames per second (%d OpenMP threads), default scene along the default walk:\n",
                omp_get_max_threads());
    std::printf("  %-32s %8s %14s %16s\n", "", "fps", "vs exact", "vs 30 Hz sensor");
    for (const auto& [name, fps] : fps_) {
      std::printf("  %-32s %8.1f %13.2fx %15.2fx\n", name.substr(0, name.find('/')).c_str(), fps, fps / exact, fps / 30.0);
    }
  }

 private:
  std::map<std::string, double> fps_;
};

}  // namespace
}  // namespace planemap::sim

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  planemap::sim::SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.PrintSummary();
  benchmark::Shutdown();
  return 0;
}
