#pragma once
// Accuracy studies: a sweep over distance, viewing angle, sensor noise, object size and segmenter.
// Every run renders a short seeded sequence of one scene object (or one frame), maps it with the
// frontend and the tracker, and scores the object's dimensions, centre and axes against the
// scene's truth, as tracking left them and after the batch back end. Runs are independent and
// deterministic: run k of a study gives the same row whoever runs it, in any order, so a study
// can run in parallel and be resumed.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/object_eval.h"
#include "planemap/core/plane_map.h"
#include "planemap/core/tum_format.h"
#include "planemap/sim/scene.h"

namespace planemap {

// The swept variables; every combination is one cell.
struct StudySweep {
  std::vector<double> distance{1.5};           // camera to the object's centre, horizontally [m]
  std::vector<double> viewing_angle_deg{45.0}; // bearing from the object's +x face normal, toward
                                               // its -y face: 0 head-on, 45 both sides alike [deg]
  std::vector<double> noise{1.0};              // depth noise scale: multiplies
                                               // render.noise.sigma_coefficient (0: exact depth) [1]
  std::vector<double> object_scale{1.0};       // the object's dimensions scaled by this [1]
  std::vector<std::string> segmenter{"organized"};  // frontend.segmentation.method

  template <class V>
  void VisitFields(V&& v) {
    v("distance", distance, Check::kPositive);
    v("viewing_angle_deg", viewing_angle_deg);
    v("noise", noise, Check::kNonNegative);
    v("object_scale", object_scale, Check::kPositive);
    v("segmenter", segmenter);
  }
};

// A study file (configs/studies/*.yaml). Paths are resolved as every command's are (the file, else
// under the source tree).
struct StudyConfig {
  std::string name = "study";
  std::string scene = "configs/scenes/default.yaml";
  std::string camera = "configs/cameras/xtion_nao.yaml";
  std::string config = "configs/default.yaml";    // the pipeline's settings
  std::string patterns = "configs/patterns.yaml";
  std::string object = "box";   // the scene object studied (by name)
  double camera_height = 1.0;   // above the floor; the camera looks at the object's centre [m]
  int frames = 5;               // frames per run: 1 scores a single frame [1]
  double path_length = 0.2;     // a run's camera moves this far on the circle around the object,
                                // centred on the cell's viewing angle [m]
  double frame_interval = 0.2;  // time between a run's frames [s]
  int seeds = 4;                // runs per cell [1]
  int seed = 1;                 // the study's base seed; run k renders with a seed derived from it
  bool backend = true;          // also score the map after the batch back end
  StudySweep sweep;

  template <class V>
  void VisitFields(V&& v) {
    v("name", name);
    v("scene", scene);
    v("camera", camera);
    v("config", config);
    v("patterns", patterns);
    v("object", object);
    v("camera_height", camera_height, Check::kPositive);
    v("frames", frames, Check::kPositive);
    v("path_length", path_length, Check::kNonNegative);
    v("frame_interval", frame_interval, Check::kPositive);
    v("seeds", seeds, Check::kPositive);
    v("seed", seed, Check::kNonNegative);
    v("backend", backend);
    v("sweep", sweep);
  }
};

// One run's place in the sweep.
struct StudyRun {
  int index = 0;  // 0-based; cells in the order distance, angle, noise, scale, segmenter (last
                  // fastest), then seeds
  double distance = 0.0, viewing_angle_deg = 0.0, noise = 0.0, object_scale = 0.0;
  std::string segmenter;
  int seed = 0;   // 1..seeds within the cell
};

// One scored map of a run: after tracking ("tracking") or the batch back end ("backend").
struct StudyRow {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  std::string source;  // what was measured: the rendered scene's name, or a real sequence's files
  StudyRun run;        // a real sequence's row: index 0.., seed 0, the swept values NaN
  std::string stage;
  bool scored = true;        // the object was scored; false where there is no object truth (a real
                             // sequence with ground-truth poses only): the object fields are empty
  bool found = false;        // a map object within eval.max_object_distance of the true centre
  std::string label;         // its class
  bool class_ok = false;
  // Estimate minus truth per true edge (the object's x, y, z), NaN where no whole edge measured
  // it; the other errors NaN when not found [m, deg].
  double dimension_error[3] = {kNaN, kNaN, kNaN};
  double center_error = kNaN;
  double axis_error_deg = kNaN;        // the estimate's x axis to the nearest true face normal
  double grasp_axis_error_deg = kNaN;  // the grasp axis to the nearest true face normal
  int frames_tracked = 0;    // frames the tracker gave a pose (not lost)
  double pose_error = kNaN;  // the camera's largest position error over the run's frames [m]
  std::string note;          // why nothing was found, when it was not
};

// Fills `row`'s object fields (found, class, errors) from an object's evaluation against the
// estimates it was matched among.
void ScoreObject(const ObjectError& error, const std::vector<ObjectEstimate>& estimates, StudyRow* row);

// Loads and checks a study file: unknown keys, empty sweeps, an unknown segmenter or object, or a
// viewpoint outside the scene's floor give an InputError naming the file (and key).
StudyConfig LoadStudy(const std::string& file);

// Every run of the study, in index order.
std::vector<StudyRun> StudyRuns(const StudyConfig& study);

// One machine's part of a study split across a cluster (a Slurm job array): shard k of n. The
// runs are dealt in index order as players pick in a draft: the first n one each to shards 1 .. n,
// the next n back from shard n to 1, and so on. Every shard gets the same number of runs (give or
// take one) and one of every n neighbours in the sweep's order, so each distance, noise level,
// ... in the same share; turning at each end cancels the sweep's fast pattern (seeds within a
// segmenter), which a plain round robin (run i to shard i mod n + 1) keeps: with the default
// study's 2 segmenters x 4 seeds, 8 shards would put every MSAC run (about 25 times an organized
// one's cost) in shards 5 to 8, where the draft gives every shard 7 or 8 of the 60.
struct StudyShard {
  int k = 1;  // 1..n
  int n = 1;  // shards in all
};

// Parses --shard's "K/N"; an InputError says what is wrong with any other text ("x", "0/4",
// "5/4", "3/0").
StudyShard ParseStudyShard(const std::string& text);

// The shard (1..n) that run `index` (0-based) is dealt to, of n.
int StudyShardOf(int index, int n);

// The shard's runs among all of a study's, in index order.
std::vector<StudyRun> ShardRuns(const std::vector<StudyRun>& runs, const StudyShard& shard);

// The shard's folder name inside the study folder's shards/: "K-of-N".
std::string StudyShardName(const StudyShard& shard);

// The scene a run renders: the study's scene with its object's dimensions scaled by
// `object_scale` about its centre's footprint, its bottom kept where it was (on the floor).
sim::Scene StudyScene(const StudyConfig& study, double object_scale);

// What a run saw, for a report: the map after tracking, the true and the tracked camera poses.
struct StudyRunMap {
  PlaneMap map;
  Trajectory truth, tracked;
};

// Renders, maps and scores one run: one row, two with the back end. Single-threaded and
// deterministic; throws InputError for unreadable inputs. `seen`, if given, receives the map.
std::vector<StudyRow> RunStudyCell(const StudyConfig& study, const StudyRun& run, StudyRunMap* seen = nullptr);

// The errors of a set of rows, absolute: dimensions (every edge measured) and centres [cm], axes
// [deg].
struct StudyErrors {
  int runs = 0, scored = 0, found = 0, class_ok = 0;
  std::vector<double> dimension, center, axis, grasp_axis, pose;  // pose: pose_error [cm]
  void Add(const StudyRow& row);
};

// The summary: per cell (the swept values and segmenter) and stage, in row order, the share of
// scored runs that found and classified the object, and the median and 90th percentile of the
// absolute dimension error (every edge measured), the centre, axis and grasp axis errors and the
// camera's pose error. As CSV, and
// printed as a table on stdout.
std::string StudySummaryCsv(const std::vector<StudyRow>& rows);
std::vector<std::string> StudySummaryLines(const std::vector<StudyRow>& rows);
void PrintStudySummary(const std::vector<StudyRow>& rows);

// The CSV of runs: one header, one line per row, units named in the header (cm, deg).
std::string StudyCsvHeader();
std::string StudyCsvLine(const StudyRow& row);
// Parses a line written by StudyCsvLine; false for a line that is not one (a truncated write).
bool ParseStudyCsvLine(const std::string& line, StudyRow* row);

}  // namespace planemap
