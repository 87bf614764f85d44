#pragma once
// One Ceres problem over a run of frames: the batch solves every frame with free landmarks and
// cuboids, the sliding window a few frames against fixed landmarks. Private to backend/.
#include <array>
#include <deque>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/normal_prior.h>

#include "planemap/backend/backend.h"
#include "planemap/factors/parameters.h"

namespace planemap::backend_detail {

struct GraphSpec {
  bool free_landmarks = true;   // else every landmark is held at the map's plane
  bool cuboids = true;          // objects of cuboid classes become boxes
  bool gauge_prior = true;      // a prior on the first pose; else the first pose is held
  int max_iterations = 50;
  bool drop_outliers = true;    // BackendConfig::outlier_rounds rounds after the first solve
  // Each frame's tracking pose as a measurement with these sigmas (0: none) [m, rad].
  double tracking_sigma = 0.0, tracking_sigma_rad = 0.0;
  bool tracking_prior_weak_only = false;  // ... on weak frames only
  // Start the plane fits' effective independent pixels at BackendConfig::noise_initial_pixels and
  // estimate them from the residuals (noise_rounds rounds); else the fits' covariances as they are.
  bool estimate_noise = false;
};

// Throws std::invalid_argument naming the setting for an unknown solver name.
ceres::LinearSolverType SolverType(const std::string& name);

class FactorGraph {
 public:
  // frames[i] starts at initial[i]. Throws std::invalid_argument on a bad config value or an
  // observation naming a landmark or object the map lacks.
  FactorGraph(const PlaneMap& map, const std::vector<const FrameObservations*>& frames, const std::vector<Pose3>& initial,
              const BackendConfig& config, const GraphSpec& spec);

  SolveReport Solve();
  Pose3 pose(size_t i) const { return PoseFromBlock(poses_[i].data()); }
  // Writes the refined landmarks and cuboid objects into `map` (the map the graph was built from).
  void Write(PlaneMap* map) const;
  // Marginal covariances of every cuboid into `map`'s objects; false with `error` when Ceres
  // could not compute them (a rank-deficient problem).
  bool Covariances(PlaneMap* map, std::string* error, double* seconds);

 private:
  struct Face {
    int cuboid = -1, axis = 0, side = 1;
  };
  struct Cuboid {
    int object = -1;
    PoseBlock pose{};
    std::array<double, 3> dimensions{};
    std::array<double, 3> edge_bias{};  // the error every view's edges share, per axis [m]
    std::array<bool, 3> held{};  // only bounded from below: held at the bound
    bool top_seen = false;       // its top face (z, +1) was observed
  };
  struct Observed;
  void AddCuboids(const std::vector<const FrameObservations*>& frames, const std::vector<Pose3>& initial);
  // (Re)adds a plane observation's residual block, whitened with its fit's covariance as if from
  // N_eff independent pixels (pixel_correlation_ = 1 / N_eff), floored.
  void AddPlaneBlock(Observed* o);
  // Variance component estimation of pixel_correlation_ (noise_estimation.h): true when it moved
  // by more than noise_tolerance (the observations are then whitened anew).
  bool UpdateNoise();
  // Drops the plane observations off their landmarks at the solution; how many went.
  int DropOutliers();
  ceres::LossFunction* Loss() const { return loss_.get(); }

  const PlaneMap& map_;
  BackendConfig config_;
  GraphSpec spec_;
  // The loss and manifolds are this graph's, shared by many blocks, and declared before problem_
  // so that they outlive it. Ceres owns only what it was given: a graph with no plane (or no
  // residual) never gave it the plane manifold (or the loss), and they leaked.
  std::unique_ptr<ceres::LossFunction> loss_;  // null: plain least squares
  std::unique_ptr<ceres::Manifold> pose_manifold_;
  std::unique_ptr<ceres::Manifold> plane_manifold_;
  std::deque<std::unique_ptr<ceres::Manifold>> dimension_manifolds_;  // a box's held dimensions
  ceres::Problem problem_{[] {
    ceres::Problem::Options options;
    options.enable_fast_removal = true;  // outlier rounds remove residual blocks
    options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return options;
  }()};
  std::deque<PoseBlock> poses_;            // deques: blocks keep their addresses
  std::map<int, PlaneBlock> landmarks_;    // by landmark id
  std::deque<Cuboid> cuboids_;
  std::map<int, Face> face_of_landmark_;
  // Plane observations (on a landmark or a box face), for the outlier rounds.
  struct Observed {
    ceres::ResidualBlockId block = nullptr;
    size_t pose = 0;
    int landmark = -1;
    const PlaneObservation* observation = nullptr;
    double normal_std = 0.0;  // the observation's own tilt [rad] and offset at its centroid [m]
    double offset_std = 0.0;  // standard deviations (floored covariance)
  };
  // The observation of a frame that saw a duplicate of the floor but not the floor: the largest
  // such; null if none.
  const PlaneObservation* FloorSeenAsDuplicate(const FrameObservations& frame, int floor) const;
  std::set<int> floor_duplicates_;  // landmarks near the floor that frames took for it
  // The world plane the graph now holds for a landmark (its block or its box's face).
  Plane WorldPlane(int landmark) const;
  std::vector<Observed> observations_;
  double pixel_correlation_ = 0.0;  // 1 / N_eff (0: the pixels independent)
  std::string noise_report_;        // what the estimation found, for SolveReport::full
};

}  // namespace planemap::backend_detail
