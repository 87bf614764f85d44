// planemap approach: one closed-loop run, or the paper's Table 1 over seeds with Fig. 8 plots.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>
#include <omp.h>

#include "app_report.h"
#include "approach_plots.h"
#include "planemap/apps/app_config.h"
#include "planemap/apps/approach.h"
#include "planemap/apps/commands.h"
#include "planemap/core/error.h"
#include "planemap/core/statistics.h"
#include "planemap/io/plane_map_io.h"

namespace planemap {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
const char* const kScenarioNames[] = {"", "open loop", "path feedback", "path feedback, then object approach"};
// The paper's Table 1 (simulation) [cm]: average error and error at the pre-grasp position.
constexpr double kPaperAverage[] = {0.0, 13.0, 8.3, 6.6};
constexpr double kPaperPregrasp[] = {0.0, 24.5, 9.1, 6.1};

double Mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}

double Std(const std::vector<double>& v) {
  const double m = Mean(v);
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  return v.size() < 2 ? 0.0 : std::sqrt(s / (v.size() - 1));
}

std::string TimingLine(const ApproachRun& r, double rate) {
  std::vector<double> total;
  for (size_t i = 0; i < r.perception_ms.size(); ++i) {
    total.push_back(r.perception_ms[i] + r.estimation_ms[i] + (i < r.control_ms.size() ? r.control_ms[i] : 0.0));
  }
  const double budget = 1000.0 / rate;
  return Printf("  time per frame (median, 95%%): perception %.1f, %.1f ms; estimation (tracking + sliding window) %.1f, %.1f ms; "
                "control %.2f, %.2f ms; together %.1f, %.1f ms against %.1f ms at %.0f Hz: %s (rendering, the simulated sensor: %.1f ms)",
                Percentile(r.perception_ms, 0.5), Percentile(r.perception_ms, 0.95), Percentile(r.estimation_ms, 0.5),
                Percentile(r.estimation_ms, 0.95), Percentile(r.control_ms, 0.5), Percentile(r.control_ms, 0.95),
                Percentile(total, 0.5), Percentile(total, 0.95), budget, rate,
                Percentile(total, 0.5) <= budget ? "keeps up" : "too slow", Percentile(r.render_ms, 0.5));
}

// What a run printed, line by line (the report's summary too).
std::vector<std::string> RunLines(const ApproachOptions& o, const ApproachRun& r) {
  std::vector<std::string> lines;
  lines.push_back(Printf("planemap approach: %s, scenario %d (%s), seed %d", o.scene.c_str(), r.scenario, kScenarioNames[r.scenario], r.seed));
  for (const nav::Viewpoint& v : r.viewpoints) {
    if (v.turn) {
      lines.push_back(Printf("  no target mapped and no view to walk to: turned on the spot at (%.2f, %.2f) m to heading %.0f deg",
                             v.pose.x, v.pose.y, v.pose.theta * kRadToDeg));
      continue;
    }
    if (v.Explores()) {
      lines.push_back(Printf("  no target mapped: explored from (%.2f, %.2f) m, heading %.0f deg, where %.1f m^2 of floor not "
                             "seen yet came into view",
                             v.pose.x, v.pose.y, v.pose.theta * kRadToDeg, v.unseen_area));
      continue;
    }
    lines.push_back(Printf("  no target mapped: looked again from (%.2f, %.2f) m, heading %.0f deg, at the face (landmark %d) "
                           "centred at (%.2f, %.2f) m",
                           v.pose.x, v.pose.y, v.pose.theta * kRadToDeg, v.candidate.landmark, v.candidate.center.x(),
                           v.candidate.center.y()));
  }
  if (!r.planned) {
    lines.push_back(Printf("  stopped before planning: %s", r.status.reason.c_str()));
    return lines;
  }
  lines.push_back(Printf("  target: %s; pre-grasp pose planned at (%.3f, %.3f) m, heading %.1f deg", r.target.c_str(), r.pregrasp_planned.x,
                         r.pregrasp_planned.y, r.pregrasp_planned.theta * kRadToDeg));
  if (r.WrongObject())
    lines.push_back(Printf("  the %s approached is not the %s the scene's task names: scored against the %s", r.target.c_str(),
                           r.intended.c_str(), r.intended.c_str()));
  lines.push_back("  stop  plan  phase      time s   estimate to path cm   truth to path cm");
  for (const ApproachStop& s : r.stops) {
    lines.push_back(Printf("  %4d  %4d  %-8s  %7.1f   %19.1f   %16.1f", s.record.index, s.record.plan,
                           s.record.phase == nav::Phase::kPath ? "path" : "approach", s.record.time, 100 * s.record.distance_to_path,
                           100 * s.truth_to_path));
  }
  lines.push_back(Printf("  %s after %.1f s (%d frames, %d lost): %s", r.Reached() ? "reached" : "stopped", r.duration, r.frames,
                         r.lost_frames, r.WrongObject() ? ("at the wrong object's pre-grasp pose: " + r.status.reason).c_str()
                                                        : r.status.reason.c_str()));
  lines.push_back(Printf("  average error %.1f cm; pre-grasp error: position %.1f cm, heading %.1f deg; grasp check: %s; collisions: %s",
                         100 * r.average_error, 100 * r.position_error, r.heading_error * kRadToDeg,
                         r.grasp_ok ? "ok" : ("failed: " + r.grasp_reason).c_str(), r.collided ? r.collision.c_str() : "none"));
  lines.push_back(Printf("  base position estimate against the truth over %zu frames: median %.1f cm, 95%% %.1f cm, worst %.1f cm",
                         r.pose_errors.size(), 100 * Percentile(r.pose_errors, 0.5), 100 * Percentile(r.pose_errors, 0.95),
                         100 * Percentile(r.pose_errors, 1.0)));
  lines.push_back(Printf("  %s estimate at the end: centre %.1f cm off; along the grasp axis %.1f cm deep (true %.1f), %.1f cm across (true %.1f)",
                         r.target.c_str(), 100 * r.object_center_error, 100 * r.object_depth, 100 * r.object_depth_true,
                         100 * r.object_width, 100 * r.object_width_true));
  lines.push_back(Printf("  gait calibration from %.2f m of tracked walking: forward scale %+.1f %% (true %+.1f), "
                         "sideways drift %+.1f cm/m (true %+.1f)",
                         r.gait.distance, 100 * r.gait.scale, 100 * r.gait.scale_true, 100 * r.gait.lateral,
                         100 * r.gait.lateral_true));
  lines.push_back(TimingLine(r, o.rate));
  return lines;
}

// The trace file, opened before the runs so that a path that cannot be written is named at once.
std::unique_ptr<std::ofstream> OpenTrace(const std::string& file) {
  if (file.empty()) return nullptr;
  auto out = std::make_unique<std::ofstream>(file);
  if (!*out) ThrowInputError(file, 0, "cannot write the trace");
  return out;
}

// Every frame of the runs as CSV, one row per frame: the columns name their units.
void WriteTrace(const std::string& file, std::ofstream& out, const std::vector<ApproachRun>& runs) {
  out << "scenario,seed,time_s,phase,status,planes,matched,inliers,added,refined,"
         "tracked_x_m,tracked_y_m,tracked_theta_rad,estimate_x_m,estimate_y_m,estimate_theta_rad,"
         "true_x_m,true_y_m,true_theta_rad,tracked_error_m,estimate_error_m,reason\n";
  for (const ApproachRun& r : runs) {
    for (const ApproachFrame& f : r.trace) {
      const bool tracked = f.status != "dropped";
      out << Printf("%d,%d,%.4f,%s,%s,%d,%d,%d,%d,%d,", r.scenario, r.seed, f.time, f.phase.c_str(), f.status.c_str(),
                    f.planes, f.matched, f.inliers, f.added, f.refined ? 1 : 0);
      out << (tracked ? Printf("%.5f,%.5f,%.5f,", f.tracked.x, f.tracked.y, f.tracked.theta) : std::string(",,,"));
      out << (f.has_estimate ? Printf("%.5f,%.5f,%.5f,", f.estimate.x, f.estimate.y, f.estimate.theta)
                             : std::string(",,,"));
      out << Printf("%.5f,%.5f,%.5f,", f.truth.x, f.truth.y, f.truth.theta);
      out << (tracked ? Printf("%.5f,", (f.tracked.Position() - f.truth.Position()).norm()) : std::string(","));
      out << (f.has_estimate ? Printf("%.5f,", (f.estimate.Position() - f.truth.Position()).norm()) : std::string(","));
      // The reason is free text: quoted, its quotes doubled (RFC 4180).
      std::string reason = f.reason;
      for (size_t at = reason.find('"'); at != std::string::npos; at = reason.find('"', at + 2)) reason.insert(at, "\"");
      out << '"' << reason << "\"\n";
    }
  }
  out.flush();
  if (!out) ThrowInputError(file, 0, "writing the trace failed");
}

void WritePlots(const std::string& prefix, const std::vector<ApproachRun>& runs) {
  for (const SvgPlot& plot : Fig8Plots(runs)) {
    std::ofstream out(prefix + plot.suffix);
    if (!out) ThrowInputError(prefix + plot.suffix, 0, "cannot write");
    out << plot.svg;
  }
}

// The run's page: its map, the robot's paths and footsteps on the floor, the control points, and
// the Fig. 8 plots. Colours as in the plots.
void WriteRunReport(const ApproachCommandOptions& options, const ApproachRun& r, const std::vector<std::string>& lines,
                    const ReportAssets& assets) {
  ReportData report;
  report.title = Printf("planemap approach: scenario %d (%s), seed %d", r.scenario, kScenarioNames[r.scenario], r.seed);
  report.summary = lines;
  const AppConfig config = LoadConfigFile<AppConfig>(ResolveConfigPath(options.run.config));
  AddMapToReport(r.map, config.frontend.graph, &report);
  const auto positions = [](const std::vector<nav::Pose2>& poses) {
    std::vector<Eigen::Vector2d> points;
    for (const nav::Pose2& p : poses) points.push_back(p.Position());
    return points;
  };
  report.paths.push_back({"reference path", "#808080", positions(r.reference), false});
  report.paths.push_back({"true base path", "#1f5fbf", positions(r.truth_path), false});
  report.paths.push_back({"estimated base path", "#ff8c00", positions(r.estimate_path), false});
  ReportPath left{"left footsteps", "#6a3d9a", {}, true, 4.0}, right{"right footsteps", "#b39ddb", {}, true, 4.0};
  for (const nav::Footstep& f : r.footsteps) (f.left ? left : right).points.push_back(f.foot.Position());
  report.paths.push_back(left);
  report.paths.push_back(right);
  ReportPath estimate{"control points: estimate", "#c0392b", {}, true}, truth{"control points: truth", "#0b3d91", {}, true};
  for (const ApproachStop& s : r.stops) {
    estimate.points.push_back(s.record.estimate.Position());
    truth.points.push_back(s.truth.Position());
  }
  report.paths.push_back(estimate);
  report.paths.push_back(truth);
  if (r.planned) report.paths.push_back({"true pre-grasp pose", "#000000", {r.pregrasp_true.Position()}, true});
  for (const SvgPlot& plot : Fig8Plots({r})) report.plots.push_back({plot.title, plot.svg});
  WriteHtmlReport(options.report, report, assets);
}

}  // namespace

int RunApproach(const ApproachCommandOptions& options) {
  // Outputs that cannot be written are named before the runs, not after them.
  if (!options.json.empty() && !options.table) throw InputError("--json writes the --table's figures; a single run has --map, --trace and --report");
  if (!options.json.empty()) CheckWritableFile(options.json);
  if (!options.map.empty() && !options.table) CheckWritableFile(options.map);
  if (!options.plots.empty()) CheckWritableFile(options.plots + "_estimate.svg");
  if (!options.table) {
    ReportAssets assets;
    if (!options.report.empty()) assets = PrepareReport(options.report);
    const std::unique_ptr<std::ofstream> trace = OpenTrace(options.trace);
    const ApproachRun r = RunApproachOnce(options.run);
    const std::vector<std::string> lines = RunLines(options.run, r);
    for (const std::string& line : lines) std::printf("%s\n", line.c_str());
    if (!options.map.empty()) {
      std::ofstream out(options.map);
      if (!out) ThrowInputError(options.map, 0, "cannot write");
      out << PlaneMapJson(r.map) << "\n";
      std::printf("  wrote %s\n", options.map.c_str());
    }
    if (!options.report.empty()) {
      WriteRunReport(options, r, lines, assets);
      std::printf("  wrote %s\n", options.report.c_str());
    }
    if (!options.plots.empty()) {
      WritePlots(options.plots, {r});
      std::printf("  wrote %s_*.svg\n", options.plots.c_str());
    }
    if (trace) {
      WriteTrace(options.trace, *trace, {r});
      std::printf("  wrote %s\n", options.trace.c_str());
    }
    return r.planned ? 0 : 1;
  }
  if (!options.report.empty() || !options.map.empty()) throw InputError("--report and --map are for a single run, not --table");
  if (options.seeds < 1) throw InputError("--seeds must be 1 or more");
  if (options.seeds > 100000) throw InputError("--seeds must be at most 100000 (3 runs each)");
  if (options.run.seed > std::numeric_limits<int>::max() - options.seeds) throw InputError("--seed + --seeds must fit in an int");
  // Every run reads the files as they are now: an edit while the table runs changes nothing.
  const std::shared_ptr<const ApproachInputs> inputs = LoadApproachInputs(options.run);
  const std::unique_ptr<std::ofstream> trace = OpenTrace(options.trace);
  // Every (scenario, seed) pair, in parallel; results in order whatever the scheduling.
  std::vector<ApproachRun> runs(3 * options.seeds);
  std::atomic<int> next{0}, done{0};
  std::mutex print;
  const int threads = options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  std::exception_ptr failure;  // the first run that threw (bad input): no further runs start
  for (int t = 0; t < std::min<int>(threads, runs.size()); ++t) {
    pool.emplace_back([&] {
      // The renderer's OpenMP loops get one thread per run: runs side by side on every core do
      // better than each run's threads spinning against the others'.
      if (threads > 1) omp_set_num_threads(1);
      for (int i = next++; i < static_cast<int>(runs.size()); i = next++) {
        ApproachOptions o = options.run;
        o.scenario = 1 + i / options.seeds;
        o.seed = options.run.seed + i % options.seeds;
        try {
          runs[i] = RunApproachOnce(o, *inputs);
        } catch (...) {
          const std::lock_guard<std::mutex> lock(print);
          if (!failure) failure = std::current_exception();
          next = static_cast<int>(runs.size());
          return;
        }
        const std::lock_guard<std::mutex> lock(print);
        std::fprintf(stderr, "\rrun %d/%zu done   ", ++done, runs.size());
      }
    });
  }
  for (std::thread& t : pool) t.join();
  std::fprintf(stderr, "\n");
  if (failure) std::rethrow_exception(failure);

  std::printf("planemap approach --table: %s, %d seeds (%d-%d) per scenario\n", options.run.scene.c_str(), options.seeds, options.run.seed,
              options.run.seed + options.seeds - 1);
  std::printf("                                       Scenario 1        Scenario 2        Scenario 3\n");
  std::vector<double> average[4], position[4], heading[4], pose_worst[4];
  int grasp_ok[4] = {}, collided[4] = {}, reached[4] = {}, wrong[4] = {};
  nlohmann::json json;
  json["scene"] = options.run.scene;
  json["seeds"] = options.seeds;
  for (const ApproachRun& r : runs) {
    if (r.planned) {
      average[r.scenario].push_back(r.average_error);
      position[r.scenario].push_back(r.position_error);
      heading[r.scenario].push_back(r.heading_error);
      pose_worst[r.scenario].push_back(Percentile(r.pose_errors, 1.0));
    }
    grasp_ok[r.scenario] += r.grasp_ok;
    collided[r.scenario] += r.collided;
    reached[r.scenario] += r.Reached();
    wrong[r.scenario] += r.WrongObject();
    nlohmann::json& s = json["scenarios"][std::to_string(r.scenario)];
    s["paper_average_error_m"] = kPaperAverage[r.scenario] / 100;
    s["paper_pregrasp_error_m"] = kPaperPregrasp[r.scenario] / 100;
    s["runs"].push_back({{"seed", r.seed}, {"planned", r.planned}, {"reached", r.Reached()}, {"reason", r.status.reason},
                         {"target", r.target}, {"intended", r.intended}, {"wrong_object", r.WrongObject()}, {"viewpoints", r.viewpoints.size()},
                         {"average_error_m", r.average_error}, {"pregrasp_position_error_m", r.position_error},
                         {"pregrasp_heading_error_rad", r.heading_error}, {"grasp_ok", r.grasp_ok}, {"collided", r.collided},
                         {"collision", r.collision}, {"duration_s", r.duration},
                         {"pose_error_median_m", Percentile(r.pose_errors, 0.5)},
                         {"pose_error_worst_m", Percentile(r.pose_errors, 1.0)},
                         {"object_center_error_m", r.object_center_error}, {"object_depth_m", r.object_depth},
                         {"object_depth_true_m", r.object_depth_true}, {"object_width_m", r.object_width},
                         {"object_width_true_m", r.object_width_true},
                         {"gait_calibration", {{"scale", r.gait.scale}, {"scale_true", r.gait.scale_true},
                                               {"lateral_m_per_m", r.gait.lateral},
                                               {"lateral_true_m_per_m", r.gait.lateral_true},
                                               {"distance_m", r.gait.distance}}}});
  }
  auto row = [&](const char* name, std::vector<double>* v, double scale) {
    std::printf("  %-36s", name);
    for (int s = 1; s <= 3; ++s) std::printf("  %5.1f +- %5.1f  ", scale * Mean(v[s]), scale * Std(v[s]));
    std::printf("\n");
  };
  row("average error [cm] mean +- std", average, 100);
  std::printf("  %-36s  %5.1f             %5.1f             %5.1f\n", "  the paper", kPaperAverage[1], kPaperAverage[2], kPaperAverage[3]);
  row("pre-grasp position error [cm]", position, 100);
  std::printf("  %-36s", "  median");
  for (int s = 1; s <= 3; ++s) std::printf("  %5.1f            ", 100 * Percentile(position[s], 0.5));
  std::printf("\n  %-36s  %5.1f             %5.1f             %5.1f\n", "  the paper", kPaperPregrasp[1], kPaperPregrasp[2], kPaperPregrasp[3]);
  row("pre-grasp heading error [deg]", heading, kRadToDeg);
  std::printf("  %-36s", "pose error, a run's worst frame [cm]");
  for (int s = 1; s <= 3; ++s) {
    std::printf("  %5.1f / %5.1f   ", 100 * Percentile(pose_worst[s], 0.5), 100 * Percentile(pose_worst[s], 1.0));
  }
  std::printf("\n  %-36s\n", "  median / worst over the runs");
  std::printf("  %-36s", "reached / grasp check ok / collided");
  for (int s = 1; s <= 3; ++s) std::printf("  %2d / %2d / %2d      ", reached[s], grasp_ok[s], collided[s]);
  std::printf("\n");
  if (wrong[1] + wrong[2] + wrong[3] > 0) {
    std::printf("  %-36s", "approached another object than the task's");
    for (int s = 1; s <= 3; ++s) std::printf("  %2d                ", wrong[s]);
    std::printf("\n");
  }
  for (int s = 1; s <= 3; ++s) {
    nlohmann::json& j = json["scenarios"][std::to_string(s)];
    j["median_pregrasp_position_error_m"] = Percentile(position[s], 0.5);
    j["grasp_ok"] = grasp_ok[s];
    j["collided"] = collided[s];
    j["wrong_object"] = wrong[s];
  }
  if (!options.json.empty()) {
    std::ofstream out(options.json);
    if (!out) ThrowInputError(options.json, 0, "cannot write");
    out << json.dump(2) << "\n";
    std::printf("  wrote %s\n", options.json.c_str());
  }
  if (!options.plots.empty()) {
    std::vector<ApproachRun> first;
    for (int s = 0; s < 3; ++s) first.push_back(runs[s * options.seeds]);
    WritePlots(options.plots, first);
    std::printf("  wrote %s_estimate.svg, %s_truth.svg, %s_approach.svg (seed %d)\n", options.plots.c_str(), options.plots.c_str(),
                options.plots.c_str(), options.run.seed);
  }
  if (trace) {
    WriteTrace(options.trace, *trace, runs);
    std::printf("  wrote %s\n", options.trace.c_str());
  }
  std::vector<double> perception, estimation, control;
  for (const ApproachRun& r : runs) {
    perception.insert(perception.end(), r.perception_ms.begin(), r.perception_ms.end());
    estimation.insert(estimation.end(), r.estimation_ms.begin(), r.estimation_ms.end());
  }
  std::printf("  time per frame over all runs (median, 95%%; runs shared the cores): perception %.1f, %.1f ms; estimation %.1f, %.1f ms\n",
              Percentile(perception, 0.5), Percentile(perception, 0.95), Percentile(estimation, 0.5), Percentile(estimation, 0.95));
  return 0;
}

}  // namespace planemap
