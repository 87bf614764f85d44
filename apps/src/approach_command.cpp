// planemap approach: one closed-loop run, or the paper's Table 1 over seeds with Fig. 8 plots.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>
#include <omp.h>

#include "planemap/apps/approach.h"
#include "planemap/apps/commands.h"
#include "planemap/core/error.h"
#include "planemap/core/statistics.h"

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

void PrintTiming(const ApproachRun& r, double rate) {
  std::vector<double> total;
  for (size_t i = 0; i < r.perception_ms.size(); ++i) {
    total.push_back(r.perception_ms[i] + r.estimation_ms[i] + (i < r.control_ms.size() ? r.control_ms[i] : 0.0));
  }
  const double budget = 1000.0 / rate;
  std::printf("  time per frame (median, 95%%): perception %.1f, %.1f ms; estimation (tracking + sliding window) %.1f, %.1f ms; "
              "control %.2f, %.2f ms; together %.1f, %.1f ms against %.1f ms at %.0f Hz: %s (rendering, the simulated sensor: %.1f ms)\n",
              Percentile(r.perception_ms, 0.5), Percentile(r.perception_ms, 0.95), Percentile(r.estimation_ms, 0.5),
              Percentile(r.estimation_ms, 0.95), Percentile(r.control_ms, 0.5), Percentile(r.control_ms, 0.95),
              Percentile(total, 0.5), Percentile(total, 0.95), budget, rate,
              Percentile(total, 0.5) <= budget ? "keeps up" : "too slow", Percentile(r.render_ms, 0.5));
}

void PrintRun(const ApproachOptions& o, const ApproachRun& r) {
  std::printf("planemap approach: %s, scenario %d (%s), seed %d\n", o.scene.c_str(), r.scenario, kScenarioNames[r.scenario], r.seed);
  if (!r.planned) {
    std::printf("  stopped before planning: %s\n", r.status.reason.c_str());
    return;
  }
  std::printf("  target: %s; pre-grasp pose planned at (%.3f, %.3f) m, heading %.1f deg\n", r.target.c_str(), r.pregrasp_planned.x,
              r.pregrasp_planned.y, r.pregrasp_planned.theta * kRadToDeg);
  std::printf("  stop  plan  phase      time s   estimate to path cm   truth to path cm\n");
  for (const ApproachStop& s : r.stops) {
    std::printf("  %4d  %4d  %-8s  %7.1f   %19.1f   %16.1f\n", s.record.index, s.record.plan,
                s.record.phase == nav::Phase::kPath ? "path" : "approach", s.record.time, 100 * s.record.distance_to_path,
                100 * s.truth_to_path);
  }
  std::printf("  %s after %.1f s (%d frames, %d lost): %s\n", r.status.Reached() ? "reached" : "stopped", r.duration, r.frames,
              r.lost_frames, r.status.reason.c_str());
  std::printf("  average error %.1f cm; pre-grasp error: position %.1f cm, heading %.1f deg; grasp check: %s; collisions: %s\n",
              100 * r.average_error, 100 * r.position_error, r.heading_error * kRadToDeg,
              r.grasp_ok ? "ok" : ("failed: " + r.grasp_reason).c_str(), r.collided ? r.collision.c_str() : "none");
  std::printf("  %s estimate at the end: centre %.1f cm off; along the grasp axis %.1f cm deep (true %.1f), %.1f cm across (true %.1f)\n",
              r.target.c_str(), 100 * r.object_center_error, 100 * r.object_depth, 100 * r.object_depth_true,
              100 * r.object_width, 100 * r.object_width_true);
  PrintTiming(r, o.rate);
}

// --- SVG plots like the paper's Fig. 8 -------------------------------------------------------
struct Series {
  std::string color, label;
  std::vector<Eigen::Vector2d> points;
  bool dots = false;
};

void WriteSvg(const std::string& file, const std::string& title, const std::string& x_label, const std::string& y_label,
              const std::vector<Series>& series, bool equal_axes) {
  Eigen::Vector2d low = Eigen::Vector2d::Constant(1e30), high = Eigen::Vector2d::Constant(-1e30);
  for (const Series& s : series) {
    for (const Eigen::Vector2d& p : s.points) {
      low = low.cwiseMin(p);
      high = high.cwiseMax(p);
    }
  }
  if (low.x() > high.x()) return;
  if (!equal_axes) low.y() = std::min(low.y(), 0.0);
  Eigen::Vector2d span = (high - low).cwiseMax(1e-6);
  const double W = 520, H = 380, L = 60, B = 50, T = 30, R = 150;
  double sx = (W - L - R) / span.x(), sy = (H - T - B) / span.y();
  if (equal_axes) sx = sy = std::min(sx, sy);
  auto X = [&](double x) { return L + (x - low.x()) * sx; };
  auto Y = [&](double y) { return H - B - (y - low.y()) * sy; };
  std::ofstream out(file);
  if (!out) ThrowInputError(file, 0, "cannot write");
  out << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H << "' font-family='sans-serif' font-size='12'>\n"
      << "<rect width='100%' height='100%' fill='white'/>\n<text x='" << L << "' y='18'>" << title << "</text>\n"
      << "<line x1='" << L << "' y1='" << H - B << "' x2='" << W - R << "' y2='" << H - B << "' stroke='black'/>\n"
      << "<line x1='" << L << "' y1='" << T << "' x2='" << L << "' y2='" << H - B << "' stroke='black'/>\n"
      << "<text x='" << (L + W - R) / 2 << "' y='" << H - 12 << "' text-anchor='middle'>" << x_label << "</text>\n"
      << "<text x='14' y='" << (T + H - B) / 2 << "' transform='rotate(-90 14 " << (T + H - B) / 2 << ")' text-anchor='middle'>" << y_label
      << "</text>\n";
  for (int i = 0; i <= 4; ++i) {
    const double vx = low.x() + span.x() * i / 4, vy = low.y() + span.y() * i / 4;
    char a[32], b[32];
    std::snprintf(a, sizeof(a), "%.2f", vx);
    std::snprintf(b, sizeof(b), "%.2f", vy);
    out << "<text x='" << X(vx) << "' y='" << H - B + 16 << "' text-anchor='middle'>" << a << "</text>\n"
        << "<text x='" << L - 6 << "' y='" << Y(vy) + 4 << "' text-anchor='end'>" << b << "</text>\n";
  }
  for (size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    out << "<polyline fill='none' stroke='" << s.color << "' stroke-width='" << (s.dots ? 0 : 2) << "' points='";
    for (const Eigen::Vector2d& p : s.points) out << X(p.x()) << ',' << Y(p.y()) << ' ';
    out << "'/>\n";
    if (s.dots) {
      for (const Eigen::Vector2d& p : s.points) out << "<circle cx='" << X(p.x()) << "' cy='" << Y(p.y()) << "' r='3' fill='" << s.color << "'/>\n";
    }
    out << "<text x='" << W - R + 10 << "' y='" << T + 16 * (k + 1) << "' fill='" << s.color << "'>" << s.label << "</text>\n";
  }
  out << "</svg>\n";
}

void WritePlots(const std::string& prefix, const std::vector<ApproachRun>& first_seed_runs) {
  const char* colors[] = {"", "red", "green", "blue"};
  std::vector<Series> left, middle;
  for (const ApproachRun& r : first_seed_runs) {
    Series e{colors[r.scenario], "scenario " + std::to_string(r.scenario), {}, true}, t = e;
    for (size_t i = 0; i < r.stops.size(); ++i) {
      e.points.emplace_back(i + 1, 100 * r.stops[i].record.distance_to_path);
      t.points.emplace_back(i + 1, 100 * r.stops[i].truth_to_path);
    }
    left.push_back(e);
    middle.push_back(t);
  }
  WriteSvg(prefix + "_estimate.svg", "Estimated position to the reference path (Fig. 8 left)", "control point", "distance [cm]", left, false);
  WriteSvg(prefix + "_truth.svg", "True position to the reference path (Fig. 8 middle)", "control point", "distance [cm]", middle, false);
  for (const ApproachRun& r : first_seed_runs) {
    if (r.scenario != 3) continue;
    std::vector<Series> top;
    Series ref{"gray", "reference path", {}, false}, truth{"blue", "true path", {}, false}, est{"orange", "estimated path", {}, false};
    for (const nav::Pose2& p : r.reference) ref.points.push_back(p.Position());
    for (const nav::Pose2& p : r.truth_path) truth.points.push_back(p.Position());
    for (const nav::Pose2& p : r.estimate_path) est.points.push_back(p.Position());
    Series goal{"black", "true pre-grasp pose", {r.pregrasp_true.Position()}, true};
    top = {ref, truth, est, goal};
    WriteSvg(prefix + "_approach.svg", "Scenario 3 approach, seen from above (Fig. 8 right)", "x [m]", "y [m]", top, true);
  }
}

}  // namespace

int RunApproach(const ApproachCommandOptions& options) {
  if (!options.table) {
    const ApproachRun r = RunApproachOnce(options.run);
    PrintRun(options.run, r);
    return r.planned ? 0 : 1;
  }
  if (options.seeds < 1) throw InputError("--seeds must be 1 or more");
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
          runs[i] = RunApproachOnce(o);
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
  std::vector<double> average[4], position[4], heading[4];
  int grasp_ok[4] = {}, collided[4] = {}, reached[4] = {};
  nlohmann::json json;
  json["scene"] = options.run.scene;
  json["seeds"] = options.seeds;
  for (const ApproachRun& r : runs) {
    if (r.planned) {
      average[r.scenario].push_back(r.average_error);
      position[r.scenario].push_back(r.position_error);
      heading[r.scenario].push_back(r.heading_error);
    }
    grasp_ok[r.scenario] += r.grasp_ok;
    collided[r.scenario] += r.collided;
    reached[r.scenario] += r.status.Reached();
    nlohmann::json& s = json["scenarios"][std::to_string(r.scenario)];
    s["paper_average_error_m"] = kPaperAverage[r.scenario] / 100;
    s["paper_pregrasp_error_m"] = kPaperPregrasp[r.scenario] / 100;
    s["runs"].push_back({{"seed", r.seed}, {"planned", r.planned}, {"reached", r.status.Reached()}, {"reason", r.status.reason},
                         {"average_error_m", r.average_error}, {"pregrasp_position_error_m", r.position_error},
                         {"pregrasp_heading_error_rad", r.heading_error}, {"grasp_ok", r.grasp_ok}, {"collided", r.collided},
                         {"collision", r.collision}, {"duration_s", r.duration},
                         {"object_center_error_m", r.object_center_error}, {"object_depth_m", r.object_depth},
                         {"object_depth_true_m", r.object_depth_true}, {"object_width_m", r.object_width},
                         {"object_width_true_m", r.object_width_true}});
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
  std::printf("  %-36s", "reached / grasp check ok / collided");
  for (int s = 1; s <= 3; ++s) std::printf("  %2d / %2d / %2d      ", reached[s], grasp_ok[s], collided[s]);
  std::printf("\n");
  for (int s = 1; s <= 3; ++s) {
    nlohmann::json& j = json["scenarios"][std::to_string(s)];
    j["median_pregrasp_position_error_m"] = Percentile(position[s], 0.5);
    j["grasp_ok"] = grasp_ok[s];
    j["collided"] = collided[s];
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
