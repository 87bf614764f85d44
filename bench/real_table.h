#pragma once
// The pure rules of bench_real (the real-data table of issue 54): which folders are sequences,
// which camera a folder gets, which frames a stride keeps, and which error a trajectory gets
// (ATE and RPE, or the first-to-last relative pose error when fewer than 3 poses have ground truth).
#include <optional>
#include <string>
#include <vector>

#include "planemap/core/pose.h"
#include "planemap/core/trajectory_eval.h"
#include "planemap/core/tum_format.h"

namespace planemap {

// A TUM-layout folder with ground truth, found under the data folder.
struct RealSequence {
  std::string dir;   // the folder
  std::string name;  // relative to the data folder ("tum_frame_pairs/fr1_xyz"); the folder's name when
                     // the data folder is the sequence itself
};

// Whether `dir` holds a TUM-layout sequence with ground truth: rgb.txt and depth.txt (or
// associations.txt), and groundtruth.txt.
bool IsSequenceWithGroundTruth(const std::string& dir);

// `data_dir` itself when it is such a sequence, else every such folder below it (subfolders of
// subfolders too), sorted by name. Throws InputError naming `data_dir` when it does not exist.
std::vector<RealSequence> FindRealSequences(const std::string& data_dir);

// The sequences named in `wanted` (by name, "tum_frame_pairs/fr1_xyz", or by folder name,
// "fr1_xyz"), in the order given; throws InputError listing the names found for an unknown one.
std::vector<RealSequence> SelectSequences(const std::vector<RealSequence>& found,
                                          const std::vector<std::string>& wanted);

// The camera file of the TUM / ICL-NUIM naming convention for a sequence name:
// fr1/freiburg1 -> configs/cameras/tum_fr1.yaml, fr2/freiburg2 -> tum_fr2.yaml,
// fr3/freiburg3 -> tum_fr3.yaml, icl -> icl_nuim.yaml (case-insensitive); nothing when none matches.
std::optional<std::string> CameraFileByName(const std::string& name);

// Frame indices 0, stride, 2 stride, ... below `frames`: the frames `planemap map --stride` uses.
std::vector<size_t> StridedFrames(size_t frames, int stride);

// The RPE's time step for frames `step` [s] apart: 1 s when a whole number of steps lies within
// 5 % of it, else the whole number of steps nearest 1 s (a tie, 1.5 steps, rounds down), so
// strided frames pair up; the pairing window is half a step.
struct RpeChoice {
  double delta = 1.0;           // [s]
  double tolerance = 0.0;       // pose pairs further than this from `delta` apart are skipped [s]
  int steps = 1;                // frame steps in delta
  bool one_second = true;       // delta is 1 s; else a footnote says why not
  bool no_pair_within = false;  // the frames span less than the nominal delta: one step instead
};
RpeChoice ChooseRpeDelta(double step);

// ChooseRpeDelta for frames at `stamps` [s] (sorted), falling back to one frame step when no two
// stamps are delta apart.
RpeChoice ChooseRpeDelta(const std::vector<double>& stamps);

// How frames at `stamps` [s] pair with the ground truth: within `max_gap` [s]. Two frames of which
// only one pairs so (a ground truth that starts just after the first frame) pair with the nearest
// poses within 0.1 s instead, and the table says how far off in time they are.
struct GroundTruthPairing {
  size_t frames = 0;            // frames with a ground-truth pose
  double max_gap = 0.0;         // the gap used [s]
  bool widened = false;         // the 2-frame fallback was taken
  double largest_offset = 0.0;  // of a frame from its ground-truth pose [s] (set when widened)
};
GroundTruthPairing PairWithGroundTruth(const Trajectory& groundtruth, const std::vector<double>& stamps,
                                       double max_gap);

// The error of the estimated motion from the first to the last frame, E = (Q_0^-1 Q_1)^-1 (P_0^-1 P_1)
// with Q the ground truth and P the estimate (as RPE, for one pair).
struct PairError {
  double translation = 0.0;   // [m]
  double rotation_deg = 0.0;  // [deg]
};
PairError RelativePoseError(const Pose3& T_world_first_true, const Pose3& T_world_last_true,
                            const Pose3& T_world_first, const Pose3& T_world_last);

// A trajectory's figures against the ground truth.
struct TrajectoryFigures {
  size_t pairs = 0;               // estimate poses with a ground-truth pose within max_time_gap
  bool ate_valid = false;         // 3 pairs or more: ATE and RPE
  double ate_rmse = 0.0;          // [m]
  bool rpe_valid = false;         // some pose pair delta apart
  RpeResult rpe;                  // [m], [deg]
  std::optional<PairError> pair;  // exactly 2 pairs: first to last
};
TrajectoryFigures EvaluateAgainstGroundTruth(const Trajectory& groundtruth, const Trajectory& estimate,
                                             const RpeChoice& rpe, double max_time_gap);

// The median spacing of the stamps [s]; 0 for fewer than 2.
double MedianStep(const std::vector<double>& stamps);

}  // namespace planemap
