// planemap study: runs a study's sweep in parallel into a resumable CSV, then prints and writes
// the summary table and plots.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>

#include <omp.h>

#include "app_report.h"
#include "parallel_runs.h"
#include "study_folder.h"
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

// --- running and writing ------------------------------------------------------------------------

// A runs.csv holding `finished`'s lines, in run order.
std::string RunsCsvText(const std::map<int, FinishedRun>& finished, int stages) {
  std::string text = StudyCsvHeader() + "\n";
  for (const auto& [index, run] : finished) {
    for (int k = 0; k < stages; ++k) text += run.lines[k] + "\n";
  }
  return text;
}

// A folder for `identity`'s runs (the whole study's, or a shard's): created, or resumed when it
// holds runs of the same settings; another study's is refused, saying what to do (`remedy`), or
// with `restart` its runs are discarded.
fs::path OpenRunFolder(const fs::path& folder, const std::string& identity, bool restart,
                       const std::string& remedy = "use another --out, or --restart to discard them") {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) ThrowInputError(folder.string(), 0, "cannot create folder: " + ec.message());
  const fs::path csv = folder / "runs.csv", identity_file = folder / "study.yaml";
  if (restart) {
    fs::remove(csv, ec);
  } else if (fs::exists(csv) && fs::exists(identity_file) && ReadText(identity_file.string()) != identity) {
    ThrowInputError(folder.string(), 0, "holds the runs of a study with other settings (its study.yaml differs): " + remedy);
  }
  WriteFileAtomically(identity_file, identity);
  return csv;
}

// What a run of the tool left in a folder's runs.csv.
struct Ran {
  std::map<int, FinishedRun> finished;  // by run index
  bool complete = false;                // every run asked for is in
  bool interrupted = false;             // Ctrl-C
};

// Runs the runs of `shard` (1/1: the whole study) that `csv` lacks, in parallel, each appended as
// it finishes; the runs an earlier invocation finished are kept. With every one in, `csv` is
// rewritten in run order, the same whatever order the runs finished in. `what` names the shard
// in what is printed.
Ran RunMissing(const StudyConfig& study, const std::vector<StudyRun>& runs, const StudyShard& shard,
               const fs::path& csv, const StudyOptions& options, const std::string& what) {
  const int stages = study.backend ? 2 : 1;
  const std::vector<StudyRun> mine = ShardRuns(runs, shard);
  int dropped = 0;
  const std::map<int, FinishedRun> before = ReadFinishedRuns(csv, runs, stages, shard, &dropped);
  const size_t resumed = before.size();
  // The file as it stands, without cut lines, so appended rows start on a line of their own.
  WriteFileAtomically(csv, RunsCsvText(before, stages));
  std::vector<StudyRun> pending;
  for (const StudyRun& run : mine) {
    if (!before.count(run.index)) pending.push_back(run);
  }
  if (options.max_runs > 0 && pending.size() > static_cast<size_t>(options.max_runs)) pending.resize(options.max_runs);

  const int threads = options.threads > 0 ? options.threads : omp_get_num_procs();
  std::fprintf(stderr, "planemap study %s%s: %zu runs (%zu cells x %d seeds)%s, %zu finished before%s, %zu to run on %d threads\n",
               study.name.c_str(), what.c_str(), runs.size(), runs.size() / study.seeds, study.seeds,
               mine.size() < runs.size() ? (", " + std::to_string(mine.size()) + " of them here").c_str() : "", resumed,
               dropped ? (", " + std::to_string(dropped) + " cut or foreign lines dropped").c_str() : "", pending.size(), threads);
  std::ofstream append(csv, std::ios::app | std::ios::binary);
  if (!append) ThrowInputError(csv.string(), 0, "cannot append");
  const ParallelRuns ran = RunInParallel(
      pending.size(), threads, resumed, mine.size(), append,
      [&](size_t i) {
        std::string text;
        for (const StudyRow& row : RunStudyCell(study, pending[i])) text += StudyCsvLine(row) + "\n";
        return text;
      },
      [&](size_t i) { return "run " + std::to_string(pending[i].index); });
  append.close();
  if (!append) ThrowInputError(csv.string(), 0, "write failed");

  Ran result;
  result.interrupted = ran.interrupted;
  if (resumed + ran.done < mine.size()) {
    std::printf("planemap study %s%s: %zu of %zu runs in %s; run the same command again to resume\n", study.name.c_str(),
                what.c_str(), resumed + ran.done, mine.size(), csv.string().c_str());
    return result;
  }
  int dropped_now = 0;
  result.finished = ReadFinishedRuns(csv, runs, stages, shard, &dropped_now);
  if (result.finished.size() != mine.size()) {
    ThrowInputError(csv.string(), 0, "lost rows while running: " + std::to_string(dropped_now));
  }
  WriteFileAtomically(csv, RunsCsvText(result.finished, stages));
  result.complete = true;
  return result;
}

// The study's outputs from all its runs, the same whether they ran in this folder or were
// collected from shards: runs.csv in run order, the summary printed and in summary.csv, the
// plots, and with `report_file` the HTML page.
void WriteStudy(const fs::path& out, const StudyConfig& study, const std::vector<StudyRun>& runs,
                const std::map<int, FinishedRun>& all, const std::string& report_file, const ReportAssets& report_assets) {
  const int stages = study.backend ? 2 : 1;
  const fs::path csv = out / "runs.csv";
  std::vector<StudyRow> rows;
  for (const auto& [index, run] : all) {
    for (int k = 0; k < stages; ++k) rows.push_back(run.rows[k]);
  }
  WriteFileAtomically(csv, RunsCsvText(all, stages));
  std::printf("planemap study %s: %zu runs of %s, object '%s', %d frame%s per run\n", study.name.c_str(), runs.size(),
              study.scene.c_str(), study.object.c_str(), study.frames, study.frames == 1 ? "" : "s");
  PrintStudySummary(rows);
  WriteFileAtomically(out / "summary.csv", StudySummaryCsv(rows));
  const std::vector<ReportPlot> plots = WritePlots(out, study, rows);
  std::printf("  wrote %s, %s", csv.string().c_str(), (out / "summary.csv").string().c_str());
  for (const ReportPlot& p : plots) std::printf(", %s", p.title.c_str());
  std::printf("\n");
  if (report_file.empty()) return;
  // The page: the summary table, the plots, and in 3-D what the first run saw (run again: a run
  // is deterministic, and its map is not kept in the CSV).
  StudyRunMap seen;
  RunStudyCell(study, runs.front(), &seen);
  ReportData report;
  report.title = "planemap study " + study.name;
  report.summary.push_back(Printf("%zu runs of %s, object '%s', %d frames per run; the 3-D view is run 0 (distance %g m, "
                                  "viewing angle %g deg, noise x%g, size x%g, %s, seed %d)",
                                  runs.size(), study.scene.c_str(), study.object.c_str(), study.frames, runs[0].distance,
                                  runs[0].viewing_angle_deg, runs[0].noise, runs[0].object_scale, runs[0].segmenter.c_str(),
                                  runs[0].seed));
  for (const std::string& line : StudySummaryLines(rows)) report.summary.push_back(line);
  const AppConfig config = LoadConfigFile<AppConfig>(ResolveConfigPath(study.config));
  AddMapToReport(seen.map, config.frontend.graph, &report);
  report.trajectories = {{"tracked camera (run 0)", "#ff8c00", seen.tracked}, {"true camera (run 0)", "#1f5fbf", seen.truth}};
  report.plots = plots;
  WriteHtmlReport(report_file, report, report_assets);
  const fs::path map_file = out / "run0_map.json";
  std::ofstream(map_file) << PlaneMapJson(seen.map) << "\n";
  std::printf("  wrote %s, %s (the map it shows)\n", report_file.c_str(), map_file.string().c_str());
}

// The options that do not go together, before anything is read or run.
void CheckStudyOptions(const StudyOptions& options) {
  if (options.max_runs < 0) throw InputError("--max-runs must be 0 (all) or more");
  if (options.collect && !options.shard.empty()) throw InputError("--collect merges every shard: give it no --shard");
  if (options.collect && (options.restart || options.max_runs > 0)) {
    throw InputError("--collect runs nothing: give it no --restart or --max-runs (give those to a --shard)");
  }
  if (!options.shard.empty() && !options.report.empty()) {
    throw InputError("--report is the whole study's page: give it to --collect, not to a --shard");
  }
}

}  // namespace

int RunStudy(const StudyOptions& options) {
  CheckStudyOptions(options);
  const StudyShard shard = options.shard.empty() ? StudyShard{} : ParseStudyShard(options.shard);
  const std::string study_file = ResolveConfigPath(options.study);
  const StudyConfig study = LoadStudy(study_file);
  const std::vector<StudyRun> runs = StudyRuns(study);
  if (static_cast<size_t>(shard.n) > runs.size()) {
    throw InputError("--shard " + options.shard + ": " + study_file + " has " + std::to_string(runs.size()) +
                     " runs, too few for " + std::to_string(shard.n) + " shards");
  }
  ReportAssets report_assets;
  if (!options.report.empty()) report_assets = PrepareReport(options.report);  // fails before the runs
  const fs::path out(options.out.empty() ? "out/study_" + study.name : options.out);

  if (options.collect) {
    // The shards' runs, all there and of this study, into the folder as a whole run leaves it.
    const std::map<int, FinishedRun> all = CollectShards(out, options.study, study, runs, study.backend ? 2 : 1);
    OpenRunFolder(out, StudyIdentity(study), /*restart=*/false, "remove its runs.csv to collect the shards there");
    WriteStudy(out, study, runs, all, options.report, report_assets);
    return 0;
  }
  if (!options.shard.empty()) {
    const fs::path folder = out / "shards" / StudyShardName(shard);
    const std::string what = ", shard " + options.shard;
    const Ran ran = RunMissing(study, runs, shard, OpenRunFolder(folder, ShardIdentity(study, shard), options.restart),
                               options, what);
    if (!ran.complete) return ran.interrupted ? 130 : 0;
    std::printf("planemap study %s%s: its %zu run%s in %s; once every shard's are in: planemap study %s --collect --out %s\n",
                study.name.c_str(), what.c_str(), ran.finished.size(), ran.finished.size() == 1 ? "" : "s",
                (folder / "runs.csv").string().c_str(),
                options.study.c_str(), out.string().c_str());
    return 0;
  }
  const Ran ran = RunMissing(study, runs, shard, OpenRunFolder(out, StudyIdentity(study), options.restart), options, "");
  if (!ran.complete) return ran.interrupted ? 130 : 0;
  WriteStudy(out, study, runs, ran.finished, options.report, report_assets);
  return 0;
}

}  // namespace planemap
