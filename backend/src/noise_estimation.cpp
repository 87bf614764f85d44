#include "noise_estimation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <random>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <ceres/cost_function.h>
#include <ceres/crs_matrix.h>

#include "planemap/core/statistics.h"

namespace planemap::backend_detail {
namespace {

double NormalisedSquare(const NoiseSample& sample, double lambda) {
  const double scale = std::max(1.0, lambda * sample.pixels);
  double x = 0.0;
  for (int j = 0; j < sample.components; ++j) x += sample.squared[j] / std::max(sample.variance[j] * scale + sample.floor[j], 1e-300);
  return x / std::max(sample.redundancy, 1e-6);
}

double MedianNormalisedSquare(const std::vector<NoiseSample>& samples, double lambda) {
  std::vector<double> x;
  x.reserve(samples.size());
  for (const NoiseSample& s : samples) x.push_back(NormalisedSquare(s, lambda));
  return Percentile(std::move(x), 0.5);
}

}  // namespace

double ChiSquareMedian(int dof) {
  static constexpr std::array<double, 6> kMedian = {0.454936, 1.386294, 2.365974, 3.356694, 4.351460, 5.348121};
  return kMedian[std::clamp(dof, 1, 6) - 1];
}

double EstimatePixelCorrelation(const std::vector<NoiseSample>& samples) {
  if (samples.empty()) return 0.0;
  const double target = ChiSquareMedian(samples.front().components);
  if (MedianNormalisedSquare(samples, 0.0) <= target) return 0.0;
  if (MedianNormalisedSquare(samples, 1.0) >= target) return 1.0;
  // The median of x falls as lambda grows: bisect on log lambda, down to one pixel in 10^9.
  double low = std::log(1e-9), high = 0.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (low + high);
    (MedianNormalisedSquare(samples, std::exp(mid)) > target ? low : high) = mid;
  }
  return std::exp(0.5 * (low + high));
}

std::vector<double> RedundancyFractions(ceres::Problem* problem, const std::vector<ResidualGroup>& groups, int probes, uint32_t seed) {
  // The whole problem's Jacobian over its free variables, and where each block's rows start.
  ceres::Problem::EvaluateOptions options;
  problem->GetResidualBlocks(&options.residual_blocks);
  std::map<ceres::ResidualBlockId, int> first_row;
  int row = 0;
  for (ceres::ResidualBlockId id : options.residual_blocks) {
    first_row[id] = row;
    row += problem->GetCostFunctionForResidualBlock(id)->num_residuals();
  }
  // The free variables in the order the residual blocks first name them. Not
  // Problem::GetParameterBlocks: it lists them by address, which differs from run to run, and the
  // columns' order moves the factorization's rounding, so the same input would not give the same
  // output to the last digit.
  std::set<double*> listed;
  for (ceres::ResidualBlockId id : options.residual_blocks) {
    std::vector<double*> blocks;
    problem->GetParameterBlocksForResidualBlock(id, &blocks);
    for (double* b : blocks) {
      if (!problem->IsParameterBlockConstant(b) && listed.insert(b).second) options.parameter_blocks.push_back(b);
    }
  }
  options.apply_loss_function = true;  // the information as the solver weighs it
  ceres::CRSMatrix crs;
  if (!problem->Evaluate(options, nullptr, nullptr, nullptr, &crs)) return {};
  const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> J(crs.num_rows, crs.num_cols, static_cast<int>(crs.values.size()),
                                                                         crs.rows.data(), crs.cols.data(), crs.values.data());
  Eigen::SparseMatrix<double> H = Eigen::SparseMatrix<double>(J.transpose()) * J;
  // A direction nothing observes (a variable whose last observation went as an outlier) would
  // make H singular; a relative 1e-9 on the diagonal leaves every observed direction as it is.
  const double ridge = 1e-9 * std::max(H.diagonal().cwiseAbs().maxCoeff(), 1e-12);
  for (int i = 0; i < H.cols(); ++i) H.coeffRef(i, i) += ridge;
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(H);
  if (ldlt.info() != Eigen::Success) return {};

  // Sum over probes of z_r (J H^-1 J^T z)_r, per row.
  std::mt19937 random(seed);
  std::bernoulli_distribution sign(0.5);
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(J.rows());
  for (int p = 0; p < probes; ++p) {
    Eigen::VectorXd z(J.rows());
    for (int i = 0; i < z.size(); ++i) z[i] = sign(random) ? 1.0 : -1.0;
    const Eigen::VectorXd Jz = J.transpose() * z;
    const Eigen::VectorXd y = J * ldlt.solve(Jz);
    diagonal += z.cwiseProduct(y);
  }
  diagonal /= std::max(probes, 1);
  std::vector<double> fractions(groups.size(), 1.0);
  for (size_t g = 0; g < groups.size(); ++g) {
    double leverage = 0.0;
    int rows = 0;
    for (ceres::ResidualBlockId id : groups[g].blocks) {
      for (int r = 0; r < groups[g].rows; ++r) leverage += diagonal[first_row.at(id) + groups[g].first_row + r];
      rows += groups[g].rows;
    }
    if (rows > 0) fractions[g] = std::clamp(1.0 - leverage / rows, 0.0, 1.0);
  }
  return fractions;
}

}  // namespace planemap::backend_detail
