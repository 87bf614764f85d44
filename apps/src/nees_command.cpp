// planemap nees: the back end's box-dimension covariances against their errors over seeded runs.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <limits>
#include <mutex>
#include <thread>

#include <boost/math/distributions/chi_squared.hpp>

#include "planemap/apps/app_config.h"
#include "planemap/apps/commands.h"
#include "planemap/apps/consistency.h"
#include "planemap/core/error.h"
#include "planemap/core/object_eval.h"
#include "planemap/core/trajectory_eval.h"
#include "planemap/pipeline/mapper.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/virtual_camera.h"
#include "planemap/sim/walk.h"

namespace planemap {
namespace {

// One seeded run: render the walk, track it, refine it; the boxes' errors and NEES.
std::vector<ConsistencyRun> OneRun(const sim::Scene& scene, const CameraIntrinsics& camera, const AppConfig& base,
                                   const PatternsConfig& patterns, const Trajectory& walk, int seed) {
  AppConfig config = base;
  config.render.seed = seed;
  const sim::VirtualCamera virtual_camera(scene, camera, config.render);
  // The world is the scene's; no sliding window.
  Mapper mapper(camera, config.mapper(), patterns, walk.front().T_world_camera, /*smoothing=*/false);
  for (size_t k = 0; k < walk.size(); ++k) {
    sim::RenderedFrame rendered = virtual_camera.Render(walk[k].T_world_camera, virtual_camera.FrameSeed(static_cast<int>(k)));
    RgbdFrame frame;
    frame.depth = std::move(rendered.depth);
    frame.color = std::move(rendered.color);
    frame.stamp = walk[k].stamp;
    mapper.Add(frame);
  }
  const BatchResult batch = mapper.Refine();
  Trajectory refined;
  for (size_t k = 0; k < batch.poses.size(); ++k) refined.push_back({mapper.observations()[k].stamp, batch.poses[k]});
  // ATE only: a short walk or a wide stride leaves no pair of poses rpe_delta apart for the RPE.
  const double ate = ComputeAte(AssociatePoses(walk, refined, config.eval.max_time_gap)).translation.rmse;
  EvalConfig eval = config.eval;
  eval.object_types = {"box"};
  std::vector<ConsistencyRun> runs;
  for (const ObjectError& e : EvaluateObjects(sim::ObjectTruths(scene), MapObjectEstimates(batch.map), eval)) {
    if (!e.found()) {
      if (std::getenv("PLANEMAP_TRACE")) std::fprintf(stderr, "seed %d: %s not in the map\n", seed, e.name.c_str());
      continue;
    }
    const MapObject& o = batch.map.objects[e.estimate];
    if (!o.uncertainty.known) {
      if (std::getenv("PLANEMAP_TRACE")) std::fprintf(stderr, "seed %d: %s is a %s, %s\n", seed, e.name.c_str(), o.label.c_str(), batch.covariance_error.c_str());
      continue;
    }
    ConsistencyRun run;
    run.seed = seed;
    run.object = e.name;
    run.error = e.dimension_error;
    run.std = o.uncertainty.dimension_std;
    run.ate = ate;
    std::vector<int> measured;
    for (int k = 0; k < 3; ++k) {
      if (o.uncertainty.dimension_std[k] > 0.0 && std::isfinite(e.dimension_error[k])) measured.push_back(k);
    }
    run.dof = static_cast<int>(measured.size());
    Eigen::VectorXd x(run.dof);
    Eigen::MatrixXd C(run.dof, run.dof);
    for (int i = 0; i < run.dof; ++i) {
      x[i] = e.dimension_error[measured[i]];
      for (int j = 0; j < run.dof; ++j) C(i, j) = o.uncertainty.dimension_covariance(measured[i], measured[j]);
    }
    run.nees = run.dof > 0 ? x.dot(C.ldlt().solve(x)) : 0.0;
    runs.push_back(run);
  }
  return runs;
}

}  // namespace

double ChiSquareQuantile(double p, int k) { return boost::math::quantile(boost::math::chi_squared(k), p); }

ConsistencyResult RunConsistencyStudy(const ConsistencyOptions& options) {
  if (options.runs < 1) throw InputError("--runs must be 1 or more");
  if (options.stride < 1) throw InputError("--stride must be 1 or more");
  if (options.first_seed < 0) throw InputError("--seed must be 0 or more");
  if (options.first_seed > std::numeric_limits<int>::max() - options.runs) throw InputError("--seed + --runs must fit in an int");
  const sim::Scene scene = sim::LoadScene(ResolveConfigPath(options.scene));
  const CameraIntrinsics camera = LoadCameraIntrinsics(ResolveConfigPath(options.camera));
  const AppConfig config = LoadConfigFile<AppConfig>(ResolveConfigPath(options.config));
  const PatternsConfig patterns = LoadPatterns(ResolveConfigPath(options.patterns));
  const Trajectory full = sim::LoadTrajectory(ResolveConfigPath(options.trajectory));
  Trajectory walk;
  for (size_t k = 0; k < full.size(); k += options.stride) walk.push_back(full[k]);
  if (walk.size() < 2) ThrowInputError(options.trajectory, 0, "the walk has fewer than two poses at this stride");

  // Runs in parallel, each on its own seed; results in run order whatever the scheduling.
  std::vector<std::vector<ConsistencyRun>> per_run(options.runs);
  std::atomic<int> next{0}, done{0};
  std::mutex print;
  std::exception_ptr failure;  // the first run that threw: no further runs start
  const int threads = options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (int t = 0; t < std::min(threads, options.runs); ++t) {
    pool.emplace_back([&] {
      for (int i = next++; i < options.runs; i = next++) {
        try {
          per_run[i] = OneRun(scene, camera, config, patterns, walk, options.first_seed + i);
        } catch (...) {
          const std::lock_guard<std::mutex> lock(print);
          if (!failure) failure = std::current_exception();
          next = options.runs;
          return;
        }
        const std::lock_guard<std::mutex> lock(print);
        std::fprintf(stderr, "\rrun %d/%d done   ", ++done, options.runs);
      }
    });
  }
  for (std::thread& t : pool) t.join();
  std::fprintf(stderr, "\n");
  if (failure) std::rethrow_exception(failure);

  ConsistencyResult result;
  for (const auto& runs : per_run) {
    if (runs.empty()) ++result.missing;
    for (const ConsistencyRun& r : runs) {
      result.runs.push_back(r);
      result.nees_sum += r.nees;
      result.dof += r.dof;
    }
  }
  if (result.dof > 0) {
    result.anees = result.nees_sum / result.dof;
    result.low = ChiSquareQuantile(0.025, result.dof) / result.dof;
    result.high = ChiSquareQuantile(0.975, result.dof) / result.dof;
  }
  return result;
}

int RunNees(const ConsistencyOptions& options) {
  std::ofstream csv;  // opened before the runs: a path that cannot be written fails at once, not after them
  if (!options.csv.empty()) {
    csv.open(options.csv);
    if (!csv) ThrowInputError(options.csv, 0, "cannot write");
  }
  const ConsistencyResult r = RunConsistencyStudy(options);
  std::printf("planemap nees: %s, walk %s every %d poses, %d runs (seeds %d-%d)\n", options.scene.c_str(), options.trajectory.c_str(),
              options.stride, options.runs, options.first_seed, options.first_seed + options.runs - 1);
  std::printf("  seed  box       dimension error [mm]        std [mm]              NEES  dof  ATE [mm]\n");
  if (csv.is_open()) {
    csv << "seed,object,error_x,error_y,error_z,std_x,std_y,std_z,nees,dof,ate\n";
  }
  for (const ConsistencyRun& run : r.runs) {
    std::printf("  %4d  %-8s %+6.2f %+6.2f %+6.2f    %5.2f %5.2f %5.2f   %6.2f  %d    %.2f\n", run.seed, run.object.c_str(),
                1000 * run.error.x(), 1000 * run.error.y(), 1000 * run.error.z(), 1000 * run.std.x(), 1000 * run.std.y(),
                1000 * run.std.z(), run.nees, run.dof, 1000 * run.ate);
    if (csv.is_open()) {
      csv << run.seed << ',' << run.object << ',' << run.error.x() << ',' << run.error.y() << ',' << run.error.z() << ',' << run.std.x()
          << ',' << run.std.y() << ',' << run.std.z() << ',' << run.nees << ',' << run.dof << ',' << run.ate << "\n";
    }
  }
  if (csv.is_open()) {
    csv.close();
    if (!csv) ThrowInputError(options.csv, 0, "write failed");
    std::printf("  wrote %s\n", options.csv.c_str());
  }
  if (r.missing > 0) std::printf("  %d runs refined no box with an uncertainty\n", r.missing);
  if (r.dof == 0) {
    std::printf("no measured box dimension in any run: no NEES\n");
    return 1;
  }
  const char* verdict = r.anees < r.low ? "conservative (the covariances are larger than the errors)"
                        : r.anees > r.high ? "optimistic (the covariances are smaller than the errors)"
                                           : "consistent";
  std::printf("ANEES %.2f over %d dof (NEES %.1f per run); 95%% chi-square interval [%.2f, %.2f]: %s\n", r.anees, r.dof,
              r.nees_sum / std::max<size_t>(1, r.runs.size()), r.low, r.high, verdict);
  return 0;
}

}  // namespace planemap
