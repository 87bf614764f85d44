// planemap study: runs a study's sweep in parallel into a resumable CSV, then prints and writes
// the summary table and plots.
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include <omp.h>

#include "app_report.h"
#include "parallel_runs.h"
#include "planemap/apps/app_config.h"
#include "planemap/apps/commands.h"
#include "planemap/apps/study.h"
#include "planemap/apps/svg_plot.h"
#include "planemap/core/error.h"
#include "planemap/core/statistics.h"
#include "planemap/io/plane_map_io.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

// What decides a study's rows: its settings and the text of every file it reads. A folder made with
// other settings is not resumed into.
std::string StudyIdentity(const StudyConfig& study) {
  std::ostringstream id;
  id << "# planemap study: the settings this folder's runs.csv was made with\n" << ConfigToYaml(study) << "\n";
  for (const std::string& file : {study.config, study.scene, study.camera, study.patterns}) {
    id << "---\n# " << file << "\n" << ReadText(ResolveConfigPath(file)) << "\n";
  }
  return id.str();
}

// A finished run as read back: its rows (and their lines) by stage, tracking first.
struct FinishedRun {
  std::array<std::string, 2> lines;
  std::array<StudyRow, 2> rows;
  int stages = 0;     // rows read
  bool twice = false;  // a stage came twice: not a run this tool wrote
};

// The finished runs of an earlier, interrupted invocation, by run index. A line that is not a
// whole row of this study (cut by the interruption, or of another sweep) is dropped, and so is a
// run missing one of its stages: it runs again.
std::map<int, FinishedRun> ReadFinishedRuns(const fs::path& csv, const std::vector<StudyRun>& runs, int stages, int* dropped) {
  std::map<int, FinishedRun> finished;
  *dropped = 0;
  std::ifstream in(csv, std::ios::binary);
  if (!in) return finished;
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream lines(text);
  std::string line;
  if (!std::getline(lines, line) || line != StudyCsvHeader()) {
    ThrowInputError(csv.string(), 1, "not a planemap study CSV (its header differs); use another --out or --restart");
  }
  size_t consumed = line.size() + 1;
  while (std::getline(lines, line)) {
    consumed += line.size() + 1;
    StudyRow row;
    const bool whole = consumed <= text.size();  // the last line ends with a newline
    if (!whole || !ParseStudyCsvLine(line, &row) || row.run.index < 0 || row.run.index >= static_cast<int>(runs.size())) {
      ++*dropped;
      continue;
    }
    const StudyRun& run = runs[row.run.index];
    if (row.run.segmenter != run.segmenter || row.run.seed != run.seed || row.run.distance != run.distance ||
        row.run.viewing_angle_deg != run.viewing_angle_deg || row.run.noise != run.noise ||
        row.run.object_scale != run.object_scale) {
      ++*dropped;
      continue;
    }
    FinishedRun& f = finished[row.run.index];
    const int slot = row.stage == "tracking" ? 0 : 1;
    f.twice = f.twice || !f.lines[slot].empty();
    f.lines[slot] = line;
    f.rows[slot] = row;
    ++f.stages;
  }
  for (auto it = finished.begin(); it != finished.end();) {
    if (it->second.stages == stages && !it->second.twice) {
      ++it;
    } else {
      *dropped += it->second.stages;
      it = finished.erase(it);
    }
  }
  return finished;
}

// --- plots --------------------------------------------------------------------------------------

// Plots of each error against each swept variable with more than one value: median (solid) and
// 90th percentile (dashed) per segmenter and stage, pooled over the other variables.
std::vector<ReportPlot> WritePlots(const fs::path& out, const StudyConfig& study, const std::vector<StudyRow>& rows) {
  struct Variable {
    const char* name;
    const char* label;
    size_t values;
    std::function<double(const StudyRun&)> get;
  };
  const StudySweep& s = study.sweep;
  const Variable variables[] = {
      {"distance", "distance to the object [m]", s.distance.size(), [](const StudyRun& r) { return r.distance; }},
      {"viewing_angle", "viewing angle from the +x face [deg]", s.viewing_angle_deg.size(),
       [](const StudyRun& r) { return r.viewing_angle_deg; }},
      {"noise", "depth noise scale", s.noise.size(), [](const StudyRun& r) { return r.noise; }},
      {"object_scale", "object size scale", s.object_scale.size(), [](const StudyRun& r) { return r.object_scale; }},
  };
  struct Metric {
    const char* name;
    const char* label;
    std::vector<double> StudyErrors::*values;
  };
  const Metric metrics[] = {{"dimension", "|dimension error| [cm]", &StudyErrors::dimension},
                            {"center", "centre error [cm]", &StudyErrors::center},
                            {"axis", "axis error [deg]", &StudyErrors::axis}};
  const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"};
  std::vector<ReportPlot> written;
  for (const Variable& v : variables) {
    if (v.values < 2) continue;
    // series key (segmenter, stage) -> x -> group
    std::map<std::string, std::map<double, StudyErrors>> series;
    for (const StudyRow& r : rows) series[r.run.segmenter + ", " + r.stage][v.get(r.run)].Add(r);
    for (const Metric& m : metrics) {
      Plot plot;
      plot.title = std::string(m.label) + " against " + v.name + ": median (solid), 90th percentile (dashed)";
      plot.x_label = v.label;
      plot.y_label = m.label;
      size_t k = 0;
      for (const auto& [name, by_x] : series) {
        PlotSeries median{colors[k % 6], name, {}, true, true, false};
        PlotSeries p90{colors[k % 6], "", {}, true, false, true};
        for (const auto& [x, group] : by_x) {
          const std::vector<double>& values = group.*(m.values);
          if (values.empty()) continue;
          median.points.emplace_back(x, Percentile(values, 0.5));
          p90.points.emplace_back(x, Percentile(values, 0.9));
        }
        plot.series.push_back(median);
        plot.series.push_back(p90);
        ++k;
      }
      const fs::path file = out / (std::string(m.name) + "_vs_" + v.name + ".svg");
      WritePlotSvg(file.string(), plot);
      written.push_back({file.filename().string(), PlotSvg(plot)});
    }
  }
  return written;
}

}  // namespace

int RunStudy(const StudyOptions& options) {
  const std::string study_file = ResolveConfigPath(options.study);
  const StudyConfig study = LoadStudy(study_file);
  const std::vector<StudyRun> runs = StudyRuns(study);
  const int stages = study.backend ? 2 : 1;
  if (options.max_runs < 0) throw InputError("--max-runs must be 0 (all) or more");

  ReportAssets report_assets;
  if (!options.report.empty()) report_assets = PrepareReport(options.report);  // fails before the runs
  const fs::path out(options.out.empty() ? "out/study_" + study.name : options.out);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) ThrowInputError(out.string(), 0, "cannot create folder: " + ec.message());
  const fs::path csv = out / "runs.csv", identity_file = out / "study.yaml";
  const std::string identity = StudyIdentity(study);
  if (options.restart) {
    fs::remove(csv, ec);
  } else if (fs::exists(csv) && fs::exists(identity_file) && ReadText(identity_file.string()) != identity) {
    ThrowInputError(out.string(), 0,
                    "holds the runs of a study with other settings (its study.yaml differs): use another --out, or --restart "
                    "to discard them");
  }
  WriteFileAtomically(identity_file, identity);

  int dropped = 0;
  std::map<int, FinishedRun> finished = ReadFinishedRuns(csv, runs, stages, &dropped);
  const size_t resumed = finished.size();
  {  // the file as it stands, without cut lines, so appended rows start on a line of their own
    std::string text = StudyCsvHeader() + "\n";
    for (const auto& [index, run] : finished) {
      for (int k = 0; k < stages; ++k) text += run.lines[k] + "\n";
    }
    WriteFileAtomically(csv, text);
  }
  std::vector<StudyRun> pending;
  for (const StudyRun& run : runs) {
    if (!finished.count(run.index)) pending.push_back(run);
  }
  if (options.max_runs > 0 && pending.size() > static_cast<size_t>(options.max_runs)) pending.resize(options.max_runs);

  const int threads = options.threads > 0 ? options.threads : omp_get_num_procs();
  std::fprintf(stderr, "planemap study %s: %zu runs (%zu cells x %d seeds), %zu finished before%s, %zu to run on %d threads\n",
               study.name.c_str(), runs.size(), runs.size() / study.seeds, study.seeds, resumed,
               dropped ? (", " + std::to_string(dropped) + " cut or foreign lines dropped").c_str() : "", pending.size(), threads);

  std::ofstream append(csv, std::ios::app | std::ios::binary);
  if (!append) ThrowInputError(csv.string(), 0, "cannot append");
  const ParallelRuns ran = RunInParallel(
      pending.size(), threads, resumed, runs.size(), append,
      [&](size_t i) {
        std::string text;
        for (const StudyRow& row : RunStudyCell(study, pending[i])) text += StudyCsvLine(row) + "\n";
        return text;
      },
      [&](size_t i) { return "run " + std::to_string(pending[i].index); });
  append.close();
  if (!append) ThrowInputError(csv.string(), 0, "write failed");
  if (resumed + ran.done < runs.size()) {
    std::printf("planemap study %s: %zu of %zu runs in %s; run the same command again to resume\n", study.name.c_str(),
                resumed + ran.done, runs.size(), csv.string().c_str());
    return ran.interrupted ? 130 : 0;
  }

  // Every run is in: the CSV in run order (the same whatever order the runs finished in), then
  // the summary and plots from it.
  int dropped_now = 0;
  const std::map<int, FinishedRun> all = ReadFinishedRuns(csv, runs, stages, &dropped_now);
  if (all.size() != runs.size()) ThrowInputError(csv.string(), 0, "lost rows while running: " + std::to_string(dropped_now));
  std::string text = StudyCsvHeader() + "\n";
  std::vector<StudyRow> rows;
  for (const auto& [index, run] : all) {
    for (int k = 0; k < stages; ++k) {
      text += run.lines[k] + "\n";
      rows.push_back(run.rows[k]);
    }
  }
  WriteFileAtomically(csv, text);
  std::printf("planemap study %s: %zu runs of %s, object '%s', %d frame%s per run\n", study.name.c_str(), runs.size(),
              study.scene.c_str(), study.object.c_str(), study.frames, study.frames == 1 ? "" : "s");
  PrintStudySummary(rows);
  WriteFileAtomically(out / "summary.csv", StudySummaryCsv(rows));
  const std::vector<ReportPlot> plots = WritePlots(out, study, rows);
  std::printf("  wrote %s, %s", csv.string().c_str(), (out / "summary.csv").string().c_str());
  for (const ReportPlot& p : plots) std::printf(", %s", p.title.c_str());
  std::printf("\n");
  if (!options.report.empty()) {
    // The page: the summary table, the plots, and in 3-D what the first run saw (run again: a
    // run is deterministic, and its map is not kept in the CSV).
    StudyRunMap seen;
    RunStudyCell(study, runs.front(), &seen);
    ReportData report;
    report.title = "planemap study " + study.name;
    report.summary.push_back(Printf("%zu runs of %s, object '%s', %d frames per run; the 3-D view is run 0 (distance %g m, "
                                    "viewing angle %g deg, noise x%g, size x%g, %s, seed %d)",
                                    runs.size(), study.scene.c_str(), study.object.c_str(), study.frames, runs[0].distance,
                                    runs[0].viewing_angle_deg, runs[0].noise, runs[0].object_scale,
                                    runs[0].segmenter.c_str(), runs[0].seed));
    for (const std::string& line : StudySummaryLines(rows)) report.summary.push_back(line);
    const AppConfig config = LoadConfigFile<AppConfig>(ResolveConfigPath(study.config));
    AddMapToReport(seen.map, config.frontend.graph, &report);
    report.trajectories = {{"tracked camera (run 0)", "#ff8c00", seen.tracked}, {"true camera (run 0)", "#1f5fbf", seen.truth}};
    report.plots = plots;
    WriteHtmlReport(options.report, report, report_assets);
    const fs::path map_file = out / "run0_map.json";
    std::ofstream(map_file) << PlaneMapJson(seen.map) << "\n";
    std::printf("  wrote %s, %s (the map it shows)\n", options.report.c_str(), map_file.string().c_str());
  }
  return 0;
}

}  // namespace planemap
