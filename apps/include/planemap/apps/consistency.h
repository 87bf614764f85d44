#pragma once
// Is the back end's uncertainty honest? Many seeded renderings of one walk through a scene, each
// tracked and refined; per run the normalised estimation error squared (NEES) of each box's
// measured dimensions, e^T C^-1 e with C the dimensions' marginal covariance; over all runs the
// average per degree of freedom (ANEES) against the 95% chi-square interval. Below it the
// covariances are too large (conservative), above it too small (optimistic).
#include <string>
#include <vector>

#include <Eigen/Core>

namespace planemap {

struct ConsistencyOptions {
  std::string scene = "configs/scenes/default.yaml";
  std::string trajectory = "configs/walks/default.yaml";  // the walk (or a TUM trajectory)
  std::string camera = "configs/cameras/xtion_nao.yaml";
  std::string config = "configs/default.yaml";
  std::string patterns = "configs/patterns.yaml";
  int runs = 50;
  int first_seed = 1;  // run k renders with seed first_seed + k
  int stride = 6;      // every n-th pose of the walk (30 Hz / 6 = the paper's 5 Hz)
  int threads = 0;     // 0: every core
  std::string csv;     // per run and box; empty: none
};

struct ConsistencyRun {
  int seed = 0;
  std::string object;  // the scene's box, "" when no box was refined with an uncertainty
  Eigen::Vector3d error = Eigen::Vector3d::Zero();  // estimate - truth per box axis [m]
  Eigen::Vector3d std = Eigen::Vector3d::Zero();    // [m], -1 where only bounded
  double nees = 0.0;
  int dof = 0;         // measured dimensions
  double ate = 0.0;    // refined trajectory's ATE [m]
};

struct ConsistencyResult {
  std::vector<ConsistencyRun> runs;  // one per (run, box) found
  int missing = 0;                   // runs in which no box was refined with its uncertainty
  double nees_sum = 0.0;
  int dof = 0;
  double anees = 0.0;                // nees_sum / dof
  double low = 0.0, high = 0.0;      // the 95% interval of the ANEES when the covariances are right
};

// The p-quantile of chi-square with k degrees of freedom (Boost.Math).
double ChiSquareQuantile(double p, int k);

ConsistencyResult RunConsistencyStudy(const ConsistencyOptions& options);

}  // namespace planemap
