#pragma once
// The back end: Ceres finds the camera poses, plane landmarks and box poses and dimensions that
// agree with every observation tracking kept (DESIGN.md, "The back end model").
//   Batch (offline, `planemap map --refine`): every frame of a run. Variables: one pose per frame,
//     one landmark per plane not on a box, one cuboid (pose + 3 positive dimensions) per object of
//     a cuboid class. Factors: plane observations (PlaneObservationFactor, or BoxFaceFactor for a
//     box's face), tracking's frame-to-frame motion (RelativePoseFactor), a prior on the first pose
//     (the gauge), each view's edge lengths (EdgeLengthFactor: complete ones measure, cut ones bound
//     from below) and centre (ObjectCenterFactor), a box's contact with the floor
//     (BoxContactFactor), optional perpendicular priors. Marginal covariances of each cuboid.
//   Sliding window (live): the last N frames against the map's landmarks, the oldest held fixed;
//     each new frame gets a smoothed pose at once.
#include <deque>
#include <string>
#include <vector>

#include "planemap/backend/backend_config.h"
#include "planemap/core/observations.h"
#include "planemap/core/plane_map.h"

namespace planemap {

// What Ceres did.
struct SolveReport {
  std::string linear_solver;          // as Ceres ran it, e.g. SPARSE_SCHUR (SUITE_SPARSE)
  std::string termination;            // CONVERGENCE, NO_CONVERGENCE or FAILURE, with Ceres's message
  bool usable = false;                // the solution may be used
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;
  double seconds = 0.0;               // the whole solve
  double seconds_per_iteration = 0.0;
  double covariance_seconds = 0.0;
  int poses = 0, landmarks = 0, cuboids = 0, residual_blocks = 0;
  int observations = 0, outliers = 0;  // plane observations, and those dropped as outliers
  std::string brief;                  // Ceres's BriefReport
  std::string full;                   // Ceres's FullReport
};

struct BatchResult {
  std::vector<Pose3> poses;  // per frame of the input, refined T_world_camera
  // The input map with refined landmarks, keyframe poses and objects: a cuboid's centre, axes,
  // dimensions, grasp axis and their uncertainty. Landmark points and extents stay as tracking
  // placed them.
  PlaneMap map;
  SolveReport report;
  std::string covariance_error;  // why the covariances could not be computed; empty when they were
};

// Refines a whole run: `frames` as Tracker::observations() gives them, `map` the tracker's map
// (before landmarks are fused or renumbered). Throws std::invalid_argument on a bad config value
// (an unknown loss or solver, named) or observations that name landmarks or objects the map lacks.
BatchResult RefineBatch(const PlaneMap& map, const std::vector<FrameObservations>& frames, const BackendConfig& config);

// The live back end: call Update after each tracked frame with the tracker's map and that frame's
// observations; it returns the frame's smoothed pose.
class SlidingWindow {
 public:
  explicit SlidingWindow(const BackendConfig& config);
  Pose3 Update(const PlaneMap& map, const FrameObservations& frame);
  const SolveReport& last_report() const { return report_; }

 private:
  BackendConfig config_;
  std::deque<FrameObservations> window_;
  std::deque<Pose3> smoothed_;  // per window frame
  SolveReport report_;
};

}  // namespace planemap
