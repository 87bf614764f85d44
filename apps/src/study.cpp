#include "planemap/apps/study.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>

#include "planemap/apps/app_config.h"
#include "planemap/core/error.h"
#include "planemap/core/object_eval.h"
#include "planemap/core/statistics.h"
#include "planemap/pipeline/mapper.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/virtual_camera.h"
#include "study_internal.h"

namespace planemap {
namespace {

using study_internal::Eye;
using study_internal::Number;
using study_internal::Short;

constexpr double kCm = 100.0;  // [cm/m]

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

bool ParseDouble(const std::string& text, double* value) {
  if (text.empty()) {
    *value = StudyRow::kNaN;
    return true;
  }
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

bool ParseInt(const std::string& text, int* value) {
  double v = 0.0;
  if (text.empty() || !ParseDouble(text, &v) || v != std::floor(v)) return false;
  *value = static_cast<int>(v);
  return true;
}

StudyRow Score(const StudyRun& run, const std::string& stage, const PlaneMap& map, const ObjectTruth& truth,
               const EvalConfig& eval) {
  StudyRow row;
  row.run = run;
  row.stage = stage;
  const std::vector<ObjectEstimate> estimates = MapObjectEstimates(map);
  ScoreObject(EvaluateObjects({truth}, estimates, eval).front(), estimates, &row);
  if (!row.found) {
    row.note = "no map object within " + Short(eval.max_object_distance) + " m of the true centre (" +
               std::to_string(estimates.size()) + " objects mapped)";
  }
  return row;
}

}  // namespace

void ScoreObject(const ObjectError& e, const std::vector<ObjectEstimate>& estimates, StudyRow* row) {
  row->found = e.found();
  if (!row->found) return;
  row->label = estimates[e.estimate].label;
  row->class_ok = row->label == ExpectedClass(e.type);
  for (int k = 0; k < 3; ++k) row->dimension_error[k] = e.true_edge_error[k];
  row->center_error = e.center_error;
  row->axis_error_deg = e.axis_error_deg;
  row->grasp_axis_error_deg = e.grasp_axis_error_deg;
}

std::vector<StudyRow> RunStudyCell(const StudyConfig& study, const StudyRun& run, StudyRunMap* seen) {
  AppConfig config = LoadConfigFile<AppConfig>(ResolveConfigPath(study.config));
  config.frontend.segmentation.method = run.segmenter;
  config.render.noise.sigma_coefficient *= run.noise;
  config.render.noise.gaussian = config.render.noise.gaussian && run.noise > 0.0;
  const CameraIntrinsics camera = LoadCameraIntrinsics(ResolveConfigPath(study.camera));
  const sim::Scene scene = StudyScene(study, run.object_scale);
  const sim::SceneObject& object = scene.object(study.object);
  const sim::VirtualCamera sensor(scene, camera, config.render);
  const PatternsConfig patterns = LoadPatterns(ResolveConfigPath(study.patterns));

  // Every cell sees the same noise draws for the same seed (common random numbers), so cells
  // differ by what the sweep changes, not by luck.
  const std::uint64_t base = 1000003ULL * static_cast<std::uint64_t>(study.seed) + 1009ULL * static_cast<std::uint64_t>(run.seed);
  const Eigen::Vector3d center = object.Center();
  std::optional<Mapper> mapper;  // anchored at the true first pose; no sliding window
  int tracked = 0;
  std::vector<Pose3> truth_poses, tracked_poses;
  for (int k = 0; k < study.frames; ++k) {
    const Pose3 T_world_camera = LookAt(Eye(study, run, object, k), center);
    truth_poses.push_back(T_world_camera);
    const sim::RenderedFrame rendered = sensor.Render(T_world_camera, base + static_cast<std::uint64_t>(k));
    RgbdFrame frame;
    frame.depth = rendered.depth;
    frame.color = rendered.color;
    frame.stamp = k * study.frame_interval;
    if (!mapper) mapper.emplace(camera, config.mapper(), patterns, T_world_camera, /*smoothing=*/false);
    const TrackResult result = mapper->Add(frame).track;
    tracked += result.status != TrackStatus::kLost;
    tracked_poses.push_back(result.T_world_camera);
  }
  auto largest_error = [&](const std::vector<Pose3>& poses) {
    double largest = 0.0;
    for (size_t k = 0; k < poses.size() && k < truth_poses.size(); ++k) {
      largest = std::max(largest, (poses[k].translation() - truth_poses[k].translation()).norm());
    }
    return largest;
  };

  ObjectTruth truth;
  for (const ObjectTruth& t : sim::ObjectTruths(scene)) {
    if (t.name == object.name) truth = t;
  }
  std::vector<StudyRow> rows{Score(run, "tracking", mapper->map(), truth, config.eval)};
  rows.back().pose_error = largest_error(tracked_poses);
  if (study.backend) {
    const BatchResult batch = mapper->Refine();
    // As `planemap map --refine`: an unusable solve keeps tracking's map, and says so.
    const bool usable = batch.report.usable;
    rows.push_back(Score(run, "backend", usable ? batch.map : mapper->map(), truth, config.eval));
    rows.back().pose_error = largest_error(usable ? batch.poses : tracked_poses);
    if (!usable) rows.back().note = "back end failed (" + batch.report.termination + "): tracking's map";
  }
  if (seen) {
    seen->map = mapper->map();
    seen->truth.clear();
    seen->tracked.clear();
    for (size_t k = 0; k < truth_poses.size(); ++k) {
      seen->truth.push_back({k * study.frame_interval, truth_poses[k]});
      seen->tracked.push_back({k * study.frame_interval, tracked_poses[k]});
    }
  }
  for (StudyRow& row : rows) {
    row.source = scene.name;
    row.frames_tracked = tracked;
  }
  return rows;
}

void StudyErrors::Add(const StudyRow& r) {
  ++runs;
  scored += r.scored;
  found += r.scored && r.found;
  class_ok += r.scored && r.class_ok;
  if (!std::isnan(r.pose_error)) pose.push_back(kCm * r.pose_error);
  for (double e : r.dimension_error) {
    if (!std::isnan(e)) dimension.push_back(kCm * std::abs(e));
  }
  if (!std::isnan(r.center_error)) center.push_back(kCm * r.center_error);
  if (!std::isnan(r.axis_error_deg)) axis.push_back(r.axis_error_deg);
  if (!std::isnan(r.grasp_axis_error_deg)) grasp_axis.push_back(r.grasp_axis_error_deg);
}

namespace {

// A cell of the summary: its rows' errors, and its key fields as printed.
struct SummaryCell {
  std::vector<std::string> key;  // source, distance, angle, noise, scale, segmenter, stage
  StudyErrors errors;
};

std::vector<SummaryCell> SummaryCells(const std::vector<StudyRow>& rows) {
  std::vector<SummaryCell> cells;
  std::map<std::vector<std::string>, size_t> index;
  for (const StudyRow& r : rows) {
    std::vector<std::string> key{r.source,
                                 Short(r.run.distance),
                                 Short(r.run.viewing_angle_deg),
                                 Short(r.run.noise),
                                 Short(r.run.object_scale),
                                 r.run.segmenter,
                                 r.stage};
    auto [it, added] = index.emplace(key, cells.size());
    if (added) cells.push_back({key, {}});
    cells[it->second].errors.Add(r);
  }
  return cells;
}

// Median and 90th percentile, NaN (printed "-", written empty) for none.
std::array<double, 2> Quantiles(const std::vector<double>& values) {
  if (values.empty()) return {StudyRow::kNaN, StudyRow::kNaN};
  return {Percentile(values, 0.5), Percentile(values, 0.9)};
}

}  // namespace

std::string StudySummaryCsv(const std::vector<StudyRow>& rows) {
  std::ostringstream csv;
  csv << "source,distance_m,viewing_angle_deg,noise,object_scale,segmenter,stage,runs,found,class_ok,"
         "dimension_error_median_cm,dimension_error_p90_cm,center_error_median_cm,center_error_p90_cm,"
         "axis_error_median_deg,axis_error_p90_deg,grasp_axis_error_median_deg,grasp_axis_error_p90_deg,"
         "pose_error_median_cm,pose_error_p90_cm\n";
  for (const SummaryCell& cell : SummaryCells(rows)) {
    for (const std::string& field : cell.key) csv << field << ',';
    const StudyErrors& e = cell.errors;
    csv << e.runs << ',' << e.found << ',' << e.class_ok;
    for (const std::vector<double>* values : {&e.dimension, &e.center, &e.axis, &e.grasp_axis, &e.pose}) {
      for (double q : Quantiles(*values)) csv << ',' << Number(q);
    }
    csv << '\n';
  }
  return csv.str();
}

std::vector<std::string> StudySummaryLines(const std::vector<StudyRow>& rows) {
  std::vector<std::string> lines;
  char text[512];
  std::snprintf(text, sizeof(text), "%-10s %6s %6s %5s %5s %-9s %-8s %5s %5s | %-13s | %-13s | %-13s | %-13s | %s", "source",
                "dist m", "angle", "noise", "scale", "segmenter", "stage", "found", "class", "dimension cm", "centre cm",
                "axis deg", "grasp axis deg", "pose cm");
  lines.push_back(text);
  std::string line;
  std::snprintf(text, sizeof(text), "%-10s %6s %6s %5s %5s %-9s %-8s %5s %5s |", "", "", "deg", "", "", "", "", "", "");
  line = text;
  for (int k = 0; k < 5; ++k) {
    std::snprintf(text, sizeof(text), " %6s %6s%s", "median", "p90", k < 4 ? " |" : "");
    line += text;
  }
  lines.push_back(line);
  auto shown = [](const std::string& field) { return field.empty() ? std::string("-") : field; };
  auto share = [](int count, int of) { return of ? std::to_string(count) + "/" + std::to_string(of) : std::string("-"); };
  for (const SummaryCell& cell : SummaryCells(rows)) {
    const StudyErrors& e = cell.errors;
    std::snprintf(text, sizeof(text), "%-10s %6s %6s %5s %5s %-9s %-8s %5s %5s |", shown(cell.key[0]).c_str(),
                  shown(cell.key[1]).c_str(), shown(cell.key[2]).c_str(), shown(cell.key[3]).c_str(),
                  shown(cell.key[4]).c_str(), shown(cell.key[5]).c_str(), cell.key[6].c_str(),
                  share(e.found, e.scored).c_str(), share(e.class_ok, e.scored).c_str());
    line = text;
    for (const std::vector<double>* values : {&e.dimension, &e.center, &e.axis, &e.grasp_axis, &e.pose}) {
      const std::array<double, 2> q = Quantiles(*values);
      std::snprintf(text, sizeof(text), " %6s %6s%s", shown(Number(q[0], "%.2f")).c_str(), shown(Number(q[1], "%.2f")).c_str(),
                    values == &e.pose ? "" : " |");
      line += text;
    }
    lines.push_back(line);
  }
  return lines;
}

void PrintStudySummary(const std::vector<StudyRow>& rows) {
  for (const std::string& line : StudySummaryLines(rows)) std::printf("  %s\n", line.c_str());
}

std::string StudyCsvHeader() {
  return "source,run,distance_m,viewing_angle_deg,noise,object_scale,segmenter,seed,stage,found,class,class_ok,"
         "dimension_error_x_cm,dimension_error_y_cm,dimension_error_z_cm,center_error_cm,axis_error_deg,"
         "grasp_axis_error_deg,frames_tracked,pose_error_cm,note";
}

std::string StudyCsvLine(const StudyRow& r) {
  std::string note = r.note;
  for (char& c : note) {
    if (c == ',' || c == '\n' || c == '"') c = ';';
  }
  std::ostringstream line;
  std::string source = r.source;
  for (char& c : source) {
    if (c == ',' || c == '\n' || c == '"') c = ';';
  }
  line << source << ',' << r.run.index << ',' << Short(r.run.distance) << ',' << Short(r.run.viewing_angle_deg) << ',' << Short(r.run.noise) << ','
       << Short(r.run.object_scale) << ',' << r.run.segmenter << ',' << r.run.seed << ',' << r.stage << ',' << (r.scored ? std::to_string(r.found) : "") << ','
       << r.label << ',' << (r.scored ? std::to_string(r.class_ok) : "") << ',' << Number(kCm * r.dimension_error[0]) << ','
       << Number(kCm * r.dimension_error[1]) << ',' << Number(kCm * r.dimension_error[2]) << ',' << Number(kCm * r.center_error)
       << ',' << Number(r.axis_error_deg) << ',' << Number(r.grasp_axis_error_deg) << ',' << r.frames_tracked << ','
       << Number(kCm * r.pose_error) << ',' << note;
  return line.str();
}

bool ParseStudyCsvLine(const std::string& line, StudyRow* r) {
  std::vector<std::string> all = SplitCsv(line);
  if (all.size() != 21) return false;
  r->source = all[0];
  const std::vector<std::string> f(all.begin() + 1, all.end());  // the fields after the source
  int found = 0, class_ok = 0;
  double cm[5];
  bool ok = ParseInt(f[0], &r->run.index) && ParseDouble(f[1], &r->run.distance) &&
            ParseDouble(f[2], &r->run.viewing_angle_deg) && ParseDouble(f[3], &r->run.noise) &&
            ParseDouble(f[4], &r->run.object_scale) && ParseInt(f[6], &r->run.seed) && (f[8].empty() || ParseInt(f[8], &found)) &&
            (f[10].empty() || ParseInt(f[10], &class_ok)) && ParseDouble(f[11], &cm[0]) && ParseDouble(f[12], &cm[1]) &&
            ParseDouble(f[13], &cm[2]) && ParseDouble(f[14], &cm[3]) && ParseDouble(f[15], &r->axis_error_deg) &&
            ParseDouble(f[16], &r->grasp_axis_error_deg) && ParseInt(f[17], &r->frames_tracked) &&
            ParseDouble(f[18], &cm[4]);
  if (!ok || (f[7] != "tracking" && f[7] != "backend")) return false;
  r->run.segmenter = f[5];
  r->stage = f[7];
  r->scored = !f[8].empty();
  r->found = found != 0;
  r->label = f[9];
  r->class_ok = class_ok != 0;
  for (int k = 0; k < 3; ++k) r->dimension_error[k] = cm[k] / kCm;
  r->center_error = cm[3] / kCm;
  r->pose_error = cm[4] / kCm;
  r->note = f[19];
  return true;
}

}  // namespace planemap
