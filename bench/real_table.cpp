#include "real_table.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <limits>

#include "planemap/core/error.h"
#include "planemap/core/statistics.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr double kRpeDeltaNominal = 1.0;  // RPE "per second", as TUM's evaluate_rpe reports it [s]
// Strided frames pair up when the pairing window is half a frame step wide.
constexpr double kToleranceInSteps = 0.5;
// A multiple of the frame step half-way between two is rounded down, so a stride of 0.67 s gets
// delta = 1 step, not 2; the margin keeps stamp jitter (a few ms) from deciding that tie [steps].
constexpr double kTieMarginInSteps = 0.01;
// delta stays 1 s when a whole number of frame steps comes this close to it (TUM's evaluate_rpe
// pairs each pose with the one nearest 1 s later, so strided frames then pair about 1 s apart) [s].
constexpr double kOneSecondWithin = 0.05;
constexpr size_t kMinPairsForAte = 3;  // the rigid alignment needs 3 points
// A 2-frame sequence whose ground truth misses one frame by a little pairs within this gap: three
// frames at 30 Hz, a few millimetres of a handheld camera's motion; the offset is printed [s].
constexpr double kWidePairGap = 0.1;

Trajectory AtStamps(const std::vector<double>& stamps) {
  Trajectory poses;
  for (const double stamp : stamps) poses.push_back({stamp, Pose3::Identity()});
  return poses;
}

// The time from `stamp` to the nearest ground-truth pose [s]; the trajectory is sorted.
double NearestOffset(const Trajectory& groundtruth, double stamp) {
  const auto after = std::lower_bound(groundtruth.begin(), groundtruth.end(), stamp,
                                      [](const StampedPose& p, double t) { return p.stamp < t; });
  double offset = std::numeric_limits<double>::infinity();
  if (after != groundtruth.end()) offset = after->stamp - stamp;
  if (after != groundtruth.begin()) offset = std::min(offset, stamp - std::prev(after)->stamp);
  return offset;
}

bool IsFile(const fs::path& p) { return fs::is_regular_file(p); }

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string JoinNames(const std::vector<RealSequence>& sequences) {
  std::string names;
  for (const RealSequence& s : sequences) names += (names.empty() ? "" : ", ") + s.name;
  return names.empty() ? "none" : names;
}

}  // namespace

bool IsSequenceWithGroundTruth(const std::string& dir) {
  const fs::path root(dir);
  const bool lists =
      (IsFile(root / "rgb.txt") && IsFile(root / "depth.txt")) || IsFile(root / "associations.txt");
  return lists && IsFile(root / "groundtruth.txt");
}

std::vector<RealSequence> FindRealSequences(const std::string& data_dir) {
  if (!fs::is_directory(data_dir)) ThrowInputError(data_dir, 0, "data folder does not exist (--data)");
  const fs::path root = fs::path(data_dir).lexically_normal();
  if (IsSequenceWithGroundTruth(root.string())) {
    const fs::path name = root.has_filename() ? root.filename() : root.parent_path().filename();
    return {{root.string(), name.string()}};
  }
  std::vector<RealSequence> found;
  for (auto it = fs::recursive_directory_iterator(root, fs::directory_options::skip_permission_denied);
       it != fs::recursive_directory_iterator(); ++it) {
    if (!it->is_directory() || !IsSequenceWithGroundTruth(it->path().string())) continue;
    found.push_back({it->path().string(), fs::relative(it->path(), root).generic_string()});
    it.disable_recursion_pending();  // a sequence's rgb/ and depth/ hold images, not sequences
  }
  std::sort(found.begin(), found.end(),
            [](const RealSequence& a, const RealSequence& b) { return a.name < b.name; });
  return found;
}

std::vector<RealSequence> SelectSequences(const std::vector<RealSequence>& found,
                                          const std::vector<std::string>& wanted) {
  std::vector<RealSequence> selected;
  for (const std::string& want : wanted) {
    const auto it = std::find_if(found.begin(), found.end(), [&want](const RealSequence& s) {
      return s.name == want || fs::path(s.name).filename() == want;
    });
    if (it == found.end()) {
      ThrowInputError(
          want, 0,
          "no such sequence with ground truth in the data folder (--sequences); found: " + JoinNames(found));
    }
    selected.push_back(*it);
  }
  return selected;
}

std::optional<std::string> CameraFileByName(const std::string& name) {
  struct Rule {
    std::vector<std::string> tokens;
    std::string file;
  };
  // TUM names its sequences rgbd_dataset_freiburgN_*, and people shorten that to frN; ICL-NUIM's
  // converted sequences carry icl in their name.
  static const Rule kRules[] = {
      {{"fr1", "freiburg1"}, "configs/cameras/tum_fr1.yaml"},
      {{"fr2", "freiburg2"}, "configs/cameras/tum_fr2.yaml"},
      {{"fr3", "freiburg3"}, "configs/cameras/tum_fr3.yaml"},
      {{"icl"}, "configs/cameras/icl_nuim.yaml"},
  };
  const std::string lower = Lower(name);
  for (const Rule& rule : kRules) {
    for (const std::string& token : rule.tokens) {
      if (lower.find(token) != std::string::npos) return rule.file;
    }
  }
  return std::nullopt;
}

std::vector<size_t> StridedFrames(size_t frames, int stride) {
  std::vector<size_t> indices;
  if (stride < 1) return indices;
  for (size_t i = 0; i < frames; i += static_cast<size_t>(stride)) indices.push_back(i);
  return indices;
}

RpeChoice ChooseRpeDelta(double step) {
  RpeChoice choice;
  if (!(step > 0.0)) return choice;
  const double steps_in_delta = kRpeDeltaNominal / step;
  choice.steps = std::max(1, static_cast<int>(std::ceil(steps_in_delta - 0.5 - kTieMarginInSteps)));
  choice.one_second = std::abs(choice.steps * step - kRpeDeltaNominal) <= kOneSecondWithin;
  choice.delta = choice.one_second ? kRpeDeltaNominal : choice.steps * step;
  choice.tolerance = kToleranceInSteps * step;
  return choice;
}

RpeChoice ChooseRpeDelta(const std::vector<double>& stamps) {
  const double step = MedianStep(stamps);
  RpeChoice choice = ChooseRpeDelta(step);
  for (size_t i = 0; i < stamps.size(); ++i) {
    for (size_t j = i + 1; j < stamps.size(); ++j) {
      if (std::abs(stamps[j] - stamps[i] - choice.delta) <= choice.tolerance) return choice;
    }
  }
  RpeChoice one_step;
  one_step.delta = step;
  one_step.tolerance = kToleranceInSteps * step;
  one_step.steps = 1;
  one_step.one_second = false;
  one_step.no_pair_within = true;
  return one_step;
}

GroundTruthPairing PairWithGroundTruth(const Trajectory& groundtruth, const std::vector<double>& stamps,
                                       double max_gap) {
  GroundTruthPairing pairing;
  pairing.max_gap = max_gap;
  pairing.frames = AssociatePoses(groundtruth, AtStamps(stamps), max_gap).size();
  if (stamps.size() != 2 || pairing.frames == 2) return pairing;
  const size_t wide = AssociatePoses(groundtruth, AtStamps(stamps), kWidePairGap).size();
  if (wide != 2) return pairing;
  pairing.frames = wide;
  pairing.max_gap = kWidePairGap;
  pairing.widened = true;
  for (const double stamp : stamps)
    pairing.largest_offset = std::max(pairing.largest_offset, NearestOffset(groundtruth, stamp));
  return pairing;
}

PairError RelativePoseError(const Pose3& T_world_first_true, const Pose3& T_world_last_true,
                            const Pose3& T_world_first, const Pose3& T_world_last) {
  const Pose3 motion_true = T_world_first_true.inverse() * T_world_last_true;
  const Pose3 motion = T_world_first.inverse() * T_world_last;
  const Pose3 error = motion_true.inverse() * motion;
  return {error.translation().norm(), RotationAngle(error.linear()) * kRadToDeg};
}

TrajectoryFigures EvaluateAgainstGroundTruth(const Trajectory& groundtruth, const Trajectory& estimate,
                                             const RpeChoice& rpe, double max_time_gap) {
  TrajectoryFigures figures;
  const AssociatedPoses poses = AssociatePoses(groundtruth, estimate, max_time_gap);
  figures.pairs = poses.size();
  if (poses.size() >= kMinPairsForAte) {
    figures.ate_valid = true;
    figures.ate_rmse = ComputeAte(poses).translation.rmse;
    figures.rpe = ComputeRpe(poses, rpe.delta, rpe.tolerance);
    figures.rpe_valid = figures.rpe.translation.count > 0;
  } else if (poses.size() == 2) {
    figures.pair = RelativePoseError(poses.groundtruth.front(), poses.groundtruth.back(),
                                     poses.estimate.front(), poses.estimate.back());
  }
  return figures;
}

double MedianStep(const std::vector<double>& stamps) {
  std::vector<double> steps;
  for (size_t i = 1; i < stamps.size(); ++i) steps.push_back(stamps[i] - stamps[i - 1]);
  return Percentile(steps, 0.5);
}

}  // namespace planemap
