#pragma once
// Trajectory accuracy as the TUM RGB-D benchmark measures it: absolute trajectory error (ATE,
// evaluate_ate.py) after a rigid alignment, and relative pose error (RPE, evaluate_rpe.py) over a
// fixed time delta.
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/pose.h"
#include "planemap/core/tum_format.h"

namespace planemap {

struct EvalConfig {
  double max_time_gap = 0.02;  // estimate and ground-truth stamps further apart do not pair [s]
  double rpe_delta = 1.0;      // RPE compares the motion between poses this far apart in time [s]
  double max_object_distance = 0.5;  // a map object centre further from the true one is not it [m]
  std::vector<std::string> object_types = {"box", "locker", "open_locker"};  // scene objects evaluated
  // How map objects (in the estimate's world) are moved into the ground truth's world:
  // first_pose (where the first paired poses coincide: exact for a map anchored at either),
  // ate (the ATE alignment) or none.
  std::string object_alignment = "first_pose";

  template <class V>
  void VisitFields(V&& v) {
    v("max_time_gap", max_time_gap, Check::kPositive);
    v("rpe_delta", rpe_delta, Check::kPositive);
    v("max_object_distance", max_object_distance, Check::kPositive);
    v("object_types", object_types);
    v("object_alignment", object_alignment, OneOf{{"first_pose", "ate", "none"}});
  }
};

// Summary of a sample of non-negative errors; all 0 for an empty sample.
struct ErrorStats {
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;  // the mean of the two middle values for an even count (as numpy)
  double max = 0.0;
  size_t count = 0;
};
ErrorStats ComputeErrorStats(std::vector<double> errors);

// Estimate and ground-truth poses paired by stamp, sorted by the estimate's stamp.
struct AssociatedPoses {
  std::vector<double> stamps;       // the estimate's [s]
  std::vector<Pose3> groundtruth;   // T_world_camera of the ground truth's world
  std::vector<Pose3> estimate;      // T_world_camera of the estimate's world
  size_t size() const { return stamps.size(); }
};

// Pairs the poses like TUM's associate.py (AssociateStamps with `max_time_gap` [s]).
AssociatedPoses AssociatePoses(const Trajectory& groundtruth, const Trajectory& estimate, double max_time_gap);

struct AteResult {
  ErrorStats translation;  // |t_gt - T_gt_est t_est| per pair [m]
  // Rigid (no scale) Horn/Umeyama alignment mapping the estimate's world into the ground truth's.
  Pose3 T_groundtruth_estimate = Pose3::Identity();
};

// ATE; count 0 when fewer than 3 pairs (the alignment needs them).
AteResult ComputeAte(const AssociatedPoses& poses);

struct RpeResult {
  double delta = 0.0;      // [s]
  ErrorStats translation;  // [m]
  ErrorStats rotation;     // [deg]
};

// RPE: for each pose i, the pose j nearest in time to stamp_i + delta; E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j)
// with Q the ground truth and P the estimate. Pairs whose stamps are not delta apart within
// `tolerance` [s] (the end of the trajectory, gaps) are skipped; count 0 if none is left.
RpeResult ComputeRpe(const AssociatedPoses& poses, double delta, double tolerance);

struct TrajectoryEvaluation {
  size_t groundtruth_poses = 0;
  size_t estimate_poses = 0;
  size_t pairs = 0;  // associated poses
  AteResult ate;
  // Q_0 P_0^-1 of the earliest paired poses: the estimate's world in the ground truth's when both
  // start at the same camera pose.
  Pose3 T_groundtruth_estimate_first = Pose3::Identity();
  RpeResult rpe;
};

// Association, ATE and RPE. Throws InputError naming the file (`*_name`) when a trajectory is
// empty, fewer than 3 poses pair up, or no two poses are rpe_delta apart.
TrajectoryEvaluation EvaluateTrajectory(const Trajectory& groundtruth, const Trajectory& estimate,
                                        const EvalConfig& config, const std::string& groundtruth_name,
                                        const std::string& estimate_name);

}  // namespace planemap
