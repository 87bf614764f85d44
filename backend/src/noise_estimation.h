#pragma once
// Variance component estimation for the batch's plane observations (Foerstner 1979; Koch,
// "Parameter Estimation and Hypothesis Testing in Linear Models", ch. 3.6): after a solve, the
// observations' noise is estimated from their residuals and the problem solved again with it,
// until the estimate settles. Private to backend/.
//
// The model: a plane fit's least-squares covariance C takes its N inlier pixels as independent.
// A structured-light sensor's depth errs in blocks (its correlation window, the disparity
// steps) and its distortion bends whole surfaces, so the pixels err together and the fit is as
// good as one from N_eff independent ones:
//   Sigma = C max(1, N / N_eff) + F   (F: the configured floor),
// with lambda = 1 / N_eff the unknown. The fit's own residual spread and its inliers' extent are
// in C, so a far strip (large spread, small extent) keeps its larger tilt, and a plane's tilt
// and its shift at the centroid keep their ratio (the patch's radius).
//
// The estimate: each sample is one observation's error split into components j with squared
// error c_j, fit variance v_j and floor f_j; its normalised square
//   x(lambda) = sum_j c_j / (v_j max(1, lambda N) + f_j)
// is chi-square with as many degrees of freedom as components, times the redundancy r of its rows
// (the share of its error the fitted variables do not absorb: a residual at the solution is
// smaller than the error behind it, and a landmark seen once fits it whole, r = 0). lambda is the
// value at which the median of x / r equals the chi-square median: robust, a few wrong
// associations do not move it. Each sample's own r, not the family's: where most landmarks are
// seen once or twice (frames far apart) the family's would be an average of zeros and ones, and
// the median of x would fall on a zero.
#include <array>
#include <cstdint>
#include <vector>

#include <ceres/problem.h>

namespace planemap::backend_detail {

struct NoiseSample {
  std::array<double, 3> squared{};   // c_j
  std::array<double, 3> variance{};  // v_j, the fit's
  std::array<double, 3> floor{};     // f_j
  int components = 1;                // how many of the three are used (the degrees of freedom)
  double pixels = 1.0;               // N
  double redundancy = 1.0;           // r
};

// The median of chi-square with 1 to 6 degrees of freedom.
double ChiSquareMedian(int dof);

// lambda in [0, 1] at which the median of x(lambda) / r is ChiSquareMedian(components): 0 when
// the samples are within their fit's covariance already (the pixels independent, as on rendered
// frames) or there are none; 1 (N_eff = 1: the whole patch errs as one) at most.
double EstimatePixelCorrelation(const std::vector<NoiseSample>& samples);

// A group of residual rows: rows [first_row, first_row + rows) of each of its blocks.
struct ResidualGroup {
  std::vector<ceres::ResidualBlockId> blocks;
  int first_row = 0, rows = 1;
};

// Redundancy of each group: 1 - the sum of its rows' leverages / its rows. A row's leverage
// is its diagonal entry of the hat matrix J H^-1 J^T (J the whitened Jacobian, robust losses
// applied as the solver weighs them, H = J^T J): the share of its error the fitted variables
// absorb. Estimated as Hutchinson's diagonal, E[z . (J H^-1 J^T z)] over `probes` random sign
// vectors z drawn from `seed` (the same seed, the same result). The hat matrix is a projection,
// so a row's estimate has a standard deviation of sqrt(h (1 - h) / probes) (0.06 at most with 64
// probes) and a group's sum at most sqrt(2 h / probes). Returns an empty vector when H cannot be
// factored.
std::vector<double> RedundancyFractions(ceres::Problem* problem, const std::vector<ResidualGroup>& groups, int probes, uint32_t seed);

}  // namespace planemap::backend_detail
