// bench_real: the real-data table of issue 54. Every TUM-layout sequence with ground truth under the
// data folder, at each stride, through `planemap map --refine` (tracking, sliding window, batch) run
// as a user runs it, and through OpenCV's four rgbd odometry methods with the same camera and the
// same frames: ATE, RPE, lost and degraded frames, ms per frame.
//
//   ./build/bench/bench_real --data ../shared/data [--sequences a,b] [--strides 1,5,10,20] [--markdown]
//   [--csv FILE]
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "opencv_odometry.h"
#include "planemap/core/error.h"
#include "planemap/core/intrinsics.h"
#include "planemap/core/statistics.h"
#include "planemap/io/tum_sequence.h"
#include "planemap_run.h"
#include "real_table.h"
#include "real_table_print.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

struct Options {
  std::string data = PLANEMAP_SOURCE_DIR "/../shared/data";
  std::vector<std::string> sequences;  // empty: all
  std::vector<int> strides = {1, 5, 10, 20};
  std::string camera;  // overrides every sequence's camera
  std::string planemap = PLANEMAP_BINARY;
  std::string work;  // planemap's outputs; empty: a temporary folder, removed
  std::string csv;
  bool markdown = false;
};

// The camera a sequence is run with: --camera, else its camera.yaml, else the naming convention.
struct CameraChoice {
  std::string file;     // as passed to planemap map
  std::string printed;  // as the table shows it
};

CameraChoice ChooseCamera(const RealSequence& sequence, const std::string& override_file) {
  if (!override_file.empty()) return {override_file, override_file + " (--camera)"};
  const fs::path stored = fs::path(sequence.dir) / "camera.yaml";
  if (TumSequence::StoredCamera(sequence.dir)) return {stored.string(), sequence.name + "/camera.yaml"};
  if (const auto by_name = CameraFileByName(sequence.name)) {
    return {(fs::path(PLANEMAP_SOURCE_DIR) / *by_name).string(), *by_name};
  }
  ThrowInputError(
      sequence.dir, 0,
      "no camera.yaml, and its name holds none of fr1/freiburg1, fr2/freiburg2, fr3/freiburg3, icl: "
      "give its intrinsics with --camera FILE");
}

double Median(const std::vector<double>& values) { return Percentile(values, 0.5); }

MethodRow NamedRow(const std::string& method, const std::string& failure = "") {
  MethodRow row;
  row.method = method;
  row.failure = failure;
  return row;
}

// planemap's three rows from one `planemap map --refine` run.
std::vector<MethodRow> PlanemapRows(const PlanemapRun& run, const Trajectory& truth, const TableGroup& g) {
  std::vector<MethodRow> rows = {NamedRow("planemap tracking"), NamedRow("planemap sliding window"),
                                 NamedRow("planemap --refine")};
  if (run.exit_code != 0) {
    for (MethodRow& row : rows)
      row.failure = "planemap map exit code " + std::to_string(run.exit_code) + ": " + run.error;
    return rows;
  }
  int lost = 0, degraded = 0;
  std::vector<double> tracking_ms, window_ms;
  for (const TrackingLogRow& r : run.log) {
    lost += r.status == "lost";
    degraded += r.status == "degraded";
    tracking_ms.push_back(r.frontend_ms + r.tracking_ms);
    window_ms.push_back(r.frontend_ms + r.tracking_ms + r.window_ms);
  }
  const Trajectory* trajectories[3] = {&run.tracking, &run.smoothed, &run.refined};
  const int frames = static_cast<int>(run.log.size());
  const double batch_ms_per_frame = 1000.0 * run.refine_seconds.value_or(0.0) / std::max(frames, 1);
  const double ms[3] = {Median(tracking_ms), Median(window_ms), Median(tracking_ms) + batch_ms_per_frame};
  for (int k = 0; k < 3; ++k) {
    rows[k].figures = EvaluateAgainstGroundTruth(truth, *trajectories[k], g.rpe, g.groundtruth.max_gap);
    rows[k].lost = lost;
    rows[k].degraded = degraded;
    rows[k].ms_per_frame = ms[k];
    rows[k].frames = frames;
  }
  if (run.refined.empty()) rows[2].failure = run.refine_failure;
  if (!run.refined.empty() && !run.refine_seconds)
    rows[2].failure = "no 'refine: ... s (' line with the batch's time on stdout";
  return rows;
}

MethodRow PeerRow(const std::string& method, const TumSequence& sequence, const std::vector<size_t>& frames,
                  const TableGroup& g) {
  const auto first_truth = sequence.entry(frames.front()).T_world_camera;
  const OdometryRun run =
      RunOpenCvOdometry(method, sequence, frames, first_truth.value_or(Pose3::Identity()));
  MethodRow row = NamedRow("OpenCV " + method, run.error);
  row.is_peer = true;
  row.figures =
      EvaluateAgainstGroundTruth(sequence.groundtruth(), run.trajectory, g.rpe, g.groundtruth.max_gap);
  row.lost = run.failures;
  row.ms_per_frame = Median(run.step_ms);
  row.frames = run.frames;
  return row;
}

// The group's frames, their spacing, the RPE's delta and how many have ground truth.
TableGroup MakeGroup(const RealSequence& s, const CameraChoice& camera, const TumSequence& sequence,
                     int stride, const std::vector<size_t>& frames, double max_gap) {
  TableGroup g;
  g.sequence = s.name;
  g.camera = camera.printed;
  g.stride = stride;
  g.sequence_frames = sequence.size();
  g.strided_frames = frames.size();
  std::vector<double> stamps;
  for (const size_t i : frames) stamps.push_back(sequence.entry(i).depth.stamp);
  g.step = MedianStep(stamps);
  g.rpe = ChooseRpeDelta(stamps);
  g.groundtruth = PairWithGroundTruth(sequence.groundtruth(), stamps, max_gap);
  return g;
}

// One sequence at every stride; a stride that keeps fewer than 2 frames is skipped with a note.
std::vector<TableGroup> RunSequence(const RealSequence& s, const Options& options, const fs::path& work,
                                    double max_gap) {
  const CameraChoice camera = ChooseCamera(s, options.camera);
  const TumSequence sequence = TumSequence::Open(s.dir, LoadCameraIntrinsics(camera.file));
  std::vector<TableGroup> groups;
  for (const int stride : options.strides) {
    const std::vector<size_t> frames = StridedFrames(sequence.size(), stride);
    TableGroup g = MakeGroup(s, camera, sequence, stride, frames, max_gap);
    if (frames.size() < 2) {
      g.skipped = "the stride keeps " + std::to_string(frames.size()) + " of the sequence's " +
                  std::to_string(sequence.size()) + " frames; odometry needs 2";
      groups.push_back(g);
      continue;
    }
    std::fprintf(stderr, "bench_real: %s, stride %d: planemap map ...\n", s.name.c_str(), stride);
    const fs::path out = work / (fs::path(s.name).generic_string() + "_stride" + std::to_string(stride));
    try {
      const PlanemapRun run = RunPlanemapMap(options.planemap, s.dir, camera.file, stride, out.string());
      g.rows = PlanemapRows(run, sequence.groundtruth(), g);
    } catch (const InputError& e) {  // its outputs could not be read: the row says why
      g.rows = {NamedRow("planemap tracking", std::string("reading its outputs: ") + e.what())};
    }
    for (const std::string& method : OpenCvOdometryMethods()) {
      std::fprintf(stderr, "bench_real: %s, stride %d: OpenCV %s ...\n", s.name.c_str(), stride,
                   method.c_str());
      g.rows.push_back(PeerRow(method, sequence, frames, g));
    }
    groups.push_back(g);
  }
  return groups;
}

bool AnyPlanemapFailure(const std::vector<TableGroup>& groups) {
  for (const TableGroup& g : groups) {
    for (const MethodRow& row : g.rows) {
      if (!row.is_peer && !row.failure.empty()) return true;
    }
  }
  return false;
}

int Run(const Options& options) {
  cv::setNumThreads(1);  // the peers on one thread, so their times compare frame for frame
  const double max_gap = EvalConfig{}.max_time_gap;
  std::vector<RealSequence> sequences = FindRealSequences(options.data);
  if (!options.sequences.empty()) sequences = SelectSequences(sequences, options.sequences);
  if (sequences.empty())
    ThrowInputError(options.data, 0, "no TUM-layout sequence with groundtruth.txt in it or below it");
  const bool temporary = options.work.empty();
  const fs::path work = temporary ? fs::temp_directory_path() / ("bench_real_" + std::to_string(getpid()))
                                  : fs::path(options.work);
  std::vector<TableGroup> groups;
  bool all_opened = true;
  for (const RealSequence& s : sequences) {
    try {
      for (TableGroup& g : RunSequence(s, options, work, max_gap)) groups.push_back(std::move(g));
    } catch (const InputError& e) {  // a sequence that cannot be opened: named in the table, the others go on
      TableGroup g;
      g.sequence = s.name;
      g.stride = 0;
      g.skipped = e.what();
      groups.push_back(g);
      all_opened = false;
    }
  }
  if (temporary) fs::remove_all(work);

  for (const std::string& line : TableHeaderLines(options.data, max_gap))
    std::printf("%s%s\n", options.markdown ? "- " : "", line.c_str());
  if (options.markdown) {
    PrintMarkdownTable(groups, stdout);
  } else {
    PrintTextTable(groups, stdout);
  }
  PrintSummary(groups, options.markdown, stdout);
  if (!options.csv.empty()) WriteTableCsv(groups, options.csv);
  // The table is printed whole; a sequence not run or a planemap run that failed still fails the command
  // (CI).
  return all_opened && !AnyPlanemapFailure(groups) ? 0 : 1;
}

}  // namespace
}  // namespace planemap

int main(int argc, char** argv) {
  planemap::Options options;
  CLI::App app{
      "bench_real: the real-data table (issue 54): planemap map --refine and OpenCV's rgbd odometry side by "
      "side"};
  app.add_option("--data", options.data,
                 "A folder of TUM-layout sequences (searched with its subfolders), or one sequence")
      ->capture_default_str();
  app.add_option("--sequences", options.sequences,
                 "Only these sequences (name or relative path), comma-separated")
      ->delimiter(',');
  app.add_option("--strides", options.strides, "Strides, comma-separated")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(1, std::numeric_limits<int>::max()));
  app.add_option("--camera", options.camera,
                 "Camera intrinsics (YAML) for every sequence; default: the sequence's camera.yaml, else by "
                 "its name (fr1, fr2, "
                 "fr3, icl)");
  app.add_option("--planemap", options.planemap, "The planemap tool to run")->capture_default_str();
  app.add_option("--work", options.work,
                 "Keep planemap map's outputs in this folder (default: a temporary folder, removed)");
  app.add_option("--csv", options.csv, "Write every figure here: sequence,stride,method,metric,value,unit");
  app.add_flag("--markdown", options.markdown, "Print the table as Markdown (for the README and docs/real_data.md)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;  // as planemap: --help is 0, a bad command line 1
  }
  try {
    if (!options.csv.empty()) planemap::CheckWritableFile(options.csv, "the CSV");
    return planemap::Run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_real: error: %s\n", e.what());
    return 1;
  }
}
