// planemap eval: trajectory error (ATE, RPE) against ground truth, and the map's objects against a
// scene's true objects.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>

#include "planemap/apps/app_config.h"
#include "planemap/apps/commands.h"
#include "planemap/apps/study.h"
#include "planemap/core/error.h"
#include "planemap/core/object_eval.h"
#include "planemap/core/trajectory_eval.h"
#include "planemap/io/plane_map_io.h"
#include "planemap/sim/scene.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

constexpr double kCm = 100.0;  // [cm/m]

// --- scene --------------------------------------------------------------------------------------

// A scene file, or a rendered sequence folder (its scene.yaml).
sim::Scene LoadSceneOrSequence(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return sim::LoadScene((fs::path(path) / "scene.yaml").string());
  return sim::LoadScene(ResolveConfigPath(path));
}

// The transform that moves map objects into the ground truth's world (eval.object_alignment).
Pose3 ObjectAlignment(const TrajectoryEvaluation& result, const std::string& mode, const std::string& config_file) {
  if (mode == "first_pose") return result.T_groundtruth_estimate_first;
  if (mode == "ate") return result.ate.T_groundtruth_estimate;
  if (mode == "none") return Pose3::Identity();
  ThrowInputError(config_file, 0, "eval.object_alignment must be first_pose, ate or none, not '" + mode + "'");
}


// --- output -------------------------------------------------------------------------------------

struct ObjectReport {
  std::string map;        // map file
  std::string scene;      // scene name
  std::string alignment;  // eval.object_alignment
  std::vector<ObjectEstimate> estimates;  // in the ground truth's world
  std::vector<ObjectError> errors;
};

void PrintStatsRow(const char* name, const ErrorStats& stats, double scale, const std::string& note) {
  std::printf("  %-17s %8.2f %8.2f %8.2f %8.2f%s%s\n", name, scale * stats.rmse, scale * stats.mean,
              scale * stats.median, scale * stats.max, note.empty() ? "" : "   ", note.c_str());
}

void PrintTrajectory(const EvalOptions& options, const EvalConfig& config, const TrajectoryEvaluation& result) {
  std::printf("planemap eval: %s against %s\n", options.estimate.c_str(), options.groundtruth.c_str());
  std::printf("  poses: %zu estimated, %zu ground truth, %zu paired within %.3f s\n", result.estimate_poses,
              result.groundtruth_poses, result.pairs, config.max_time_gap);
  std::printf("  %-17s %8s %8s %8s %8s\n", "", "rmse", "mean", "median", "max");
  PrintStatsRow("ATE [cm]", result.ate.translation, kCm, "after rigid alignment");
  char name[64];
  std::snprintf(name, sizeof(name), "RPE %.2f s [cm]", result.rpe.delta);
  PrintStatsRow(name, result.rpe.translation, kCm, std::to_string(result.rpe.translation.count) + " pose pairs");
  std::snprintf(name, sizeof(name), "RPE %.2f s [deg]", result.rpe.delta);
  PrintStatsRow(name, result.rpe.rotation, 1.0, "");
  const Pose3& T = result.ate.T_groundtruth_estimate;
  std::printf("  ATE alignment of the estimate's world to the ground truth's: %.3f deg, %.2f cm\n",
              RotationAngle(T.linear()) * 180.0 / M_PI, kCm * T.translation().norm());
}

// "  1.23" or "     -" for NaN, in a field `width` wide.
std::string Cell(double value, int width, const char* format = "%*.2f") {
  char buffer[32];
  if (std::isnan(value)) std::snprintf(buffer, sizeof(buffer), "%*s", width, "-");
  else std::snprintf(buffer, sizeof(buffer), format, width, value);
  return buffer;
}

void PrintObjects(const ObjectReport& report) {
  std::printf("  objects: %zu in %s against scene %s (map aligned by %s)\n", report.estimates.size(),
              report.map.c_str(), report.scene.c_str(), report.alignment.c_str());
  std::printf("    %-12s %-12s %-8s %11s %23s %11s %12s\n", "name", "type", "class", "centre [cm]",
              "dimensions x y z [cm]", "axis [deg]", "grasp [deg]");
  for (const ObjectError& e : report.errors) {
    if (!e.found()) {
      std::printf("    %-12s %-12s %-8s %11s\n", e.name.c_str(), e.type.c_str(), "-", "not found");
      continue;
    }
    std::printf("    %-12s %-12s %-8s %s %s%s%s %s %s\n", e.name.c_str(), e.type.c_str(),
                report.estimates[e.estimate].label.c_str(), Cell(kCm * e.center_error, 11).c_str(),
                Cell(kCm * e.dimension_error.x(), 7, "%+*.2f").c_str(), Cell(kCm * e.dimension_error.y(), 8, "%+*.2f").c_str(),
                Cell(kCm * e.dimension_error.z(), 8, "%+*.2f").c_str(), Cell(e.axis_error_deg, 11).c_str(),
                Cell(e.grasp_axis_error_deg, 12).c_str());
  }
}

// Rows "kind,name,metric,value,unit"; SI units (m, s, deg); empty value where not measured.
class CsvWriter {
 public:
  explicit CsvWriter(const std::string& file) : file_(file), out_(file) {
    if (!out_) ThrowInputError(file, 0, "cannot open file for writing");
    out_ << "kind,name,metric,value,unit\n";
  }
  void Row(const std::string& kind, const std::string& name, const std::string& metric, double value,
           const std::string& unit) {
    char buffer[32] = "";
    if (!std::isnan(value)) std::snprintf(buffer, sizeof(buffer), "%.9g", value);
    Row(kind, name, metric, std::string(buffer), unit);
  }
  void Row(const std::string& kind, const std::string& name, const std::string& metric, const std::string& value,
           const std::string& unit) {
    out_ << kind << ',' << Quoted(name) << ',' << metric << ',' << Quoted(value) << ',' << unit << '\n';
  }
  void Stats(const std::string& name, const std::string& prefix, const ErrorStats& stats, const std::string& unit) {
    Row("trajectory", name, prefix + "_rmse", stats.rmse, unit);
    Row("trajectory", name, prefix + "_mean", stats.mean, unit);
    Row("trajectory", name, prefix + "_median", stats.median, unit);
    Row("trajectory", name, prefix + "_max", stats.max, unit);
  }
  void Close() {
    out_.close();
    if (!out_) ThrowInputError(file_, 0, "write failed");
  }

 private:
  static std::string Quoted(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
  }
  std::string file_;
  std::ofstream out_;
};

void WriteCsv(const std::string& file, const EvalOptions& options, const TrajectoryEvaluation& result,
              const ObjectReport* objects) {
  CsvWriter csv(file);
  const std::string name = fs::path(options.estimate).filename().string();
  csv.Row("trajectory", name, "pairs", static_cast<double>(result.pairs), "");
  csv.Stats(name, "ate", result.ate.translation, "m");
  csv.Row("trajectory", name, "rpe_delta", result.rpe.delta, "s");
  csv.Row("trajectory", name, "rpe_pairs", static_cast<double>(result.rpe.translation.count), "");
  csv.Stats(name, "rpe_translation", result.rpe.translation, "m");
  csv.Stats(name, "rpe_rotation", result.rpe.rotation, "deg");
  for (size_t i = 0; objects && i < objects->errors.size(); ++i) {
    const ObjectError& e = objects->errors[i];
    csv.Row("object", e.name, "type", e.type, "");
    csv.Row("object", e.name, "found", e.found() ? 1.0 : 0.0, "");
    if (!e.found()) continue;
    const std::string& label = objects->estimates[e.estimate].label;
    csv.Row("object", e.name, "class", label, "");
    csv.Row("object", e.name, "class_correct", label == ExpectedClass(e.type) ? 1.0 : 0.0, "");
    csv.Row("object", e.name, "center_error", e.center_error, "m");
    for (int k = 0; k < 3; ++k) csv.Row("object", e.name, std::string("dimension_error_") + "xyz"[k], e.dimension_error[k], "m");
    csv.Row("object", e.name, "axis_error", e.axis_error_deg, "deg");
    csv.Row("object", e.name, "grasp_axis_error", e.grasp_axis_error_deg, "deg");
  }
  csv.Close();
}

// The figures as rows of a study (planemap study), so real and simulated studies read alike: one
// per evaluated object, or one without object scores when there is no object truth. The pose
// error is the largest position error with the estimate's first pose on the ground truth's, as a
// study's runs are anchored.
std::vector<StudyRow> StudyRows(const EvalOptions& options, const EvalConfig& config, const Trajectory& groundtruth,
                                const Trajectory& estimate, const TrajectoryEvaluation& result, const ObjectReport* objects) {
  const AssociatedPoses pairs = AssociatePoses(groundtruth, estimate, config.max_time_gap);
  double pose_error = 0.0;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const Eigen::Vector3d t = result.T_groundtruth_estimate_first * pairs.estimate[i].translation();
    pose_error = std::max(pose_error, (t - pairs.groundtruth[i].translation()).norm());
  }
  StudyRow base;
  base.source = fs::path(options.estimate).parent_path().filename().string();
  if (base.source.empty()) base.source = fs::path(options.estimate).stem().string();
  base.run.distance = base.run.viewing_angle_deg = base.run.noise = base.run.object_scale = StudyRow::kNaN;
  base.stage = options.stage;
  base.frames_tracked = static_cast<int>(result.estimate_poses);
  base.pose_error = pose_error;
  std::vector<StudyRow> rows;
  for (size_t i = 0; objects && i < objects->errors.size(); ++i) {
    const ObjectError& e = objects->errors[i];
    const auto& types = config.object_types;
    if (std::find(types.begin(), types.end(), e.type) == types.end()) continue;
    StudyRow row = base;
    row.source = objects->scene + ":" + e.name;
    row.run.index = static_cast<int>(rows.size());
    ScoreObject(e, objects->estimates, &row);
    if (!row.found) row.note = "not found";
    rows.push_back(row);
  }
  if (rows.empty()) {
    base.scored = false;
    base.note = objects ? "no object of eval.object_types in the scene" : "no object truth: give --map and --scene";
    rows.push_back(base);
  }
  return rows;
}

}  // namespace

int RunEval(const EvalOptions& options) {
  if (options.map.empty() != options.scene.empty()) {
    throw InputError("object evaluation needs both --map MAP.json and --scene SCENE.yaml (or a rendered sequence folder)");
  }
  if (options.stage != "tracking" && options.stage != "backend") {
    throw InputError("--stage must be tracking or backend, not '" + options.stage + "'");
  }
  const std::string config_file = ResolveConfigPath(options.config);
  const EvalConfig config = LoadConfigFile<AppConfig>(config_file).eval;
  ObjectAlignment({}, config.object_alignment, config_file);  // a bad setting fails before any work
  const Trajectory groundtruth = ReadTumTrajectory(options.groundtruth);
  const Trajectory estimate = ReadTumTrajectory(options.estimate);
  const TrajectoryEvaluation result =
      EvaluateTrajectory(groundtruth, estimate, config, options.groundtruth, options.estimate);
  PrintTrajectory(options, config, result);

  std::optional<ObjectReport> objects;
  if (!options.map.empty()) {
    objects.emplace();
    objects->map = options.map;
    objects->alignment = config.object_alignment;
    const sim::Scene scene = LoadSceneOrSequence(options.scene);
    objects->scene = scene.name;
    const Pose3 T_groundtruth_map = ObjectAlignment(result, config.object_alignment, config_file);
    for (const ObjectEstimate& o : MapObjectEstimates(ReadPlaneMapJson(options.map))) {
      objects->estimates.push_back(Transformed(T_groundtruth_map, o));
    }
    objects->errors = EvaluateObjects(sim::ObjectTruths(scene), objects->estimates, config);
    PrintObjects(*objects);
  }
  if (!options.csv.empty()) {
    WriteCsv(options.csv, options, result, objects ? &*objects : nullptr);
    std::fprintf(stderr, "  wrote %s\n", options.csv.c_str());
  }
  if (!options.study_csv.empty()) {
    const std::vector<StudyRow> rows = StudyRows(options, config, groundtruth, estimate, result, objects ? &*objects : nullptr);
    std::ofstream out(options.study_csv);
    out << StudyCsvHeader() << "\n";
    for (const StudyRow& row : rows) out << StudyCsvLine(row) << "\n";
    out.close();
    if (!out) ThrowInputError(options.study_csv, 0, "cannot write");
    std::printf("  as a study (planemap study's columns, in %s):\n", options.study_csv.c_str());
    PrintStudySummary(rows);
  }
  return 0;
}

}  // namespace planemap
