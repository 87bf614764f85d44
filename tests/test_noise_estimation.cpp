// The batch's noise estimation (backend/src/noise_estimation.h): the effective number of
// independent pixels recovered from simulated plane-fit errors, none where the pixels are
// independent, and residual redundancies against the closed form of a mean's.
#include <algorithm>
#include <cmath>
#include <random>

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "../backend/src/noise_estimation.h"  // internal: the batch's variance component estimation

namespace planemap::backend_detail {
namespace {

// Tilt errors of plane fits of 1000-50000 pixels from patches of 0.1-1 m radius with 2 mm pixel
// noise: each fit's variance is sigma^2 / (N r^2); the error is drawn with that variance times
// max(1, N / n_eff) (n_eff 0: the fit's variance), and scaled by sqrt(redundancy) as a residual
// at a solution would be.
std::vector<NoiseSample> SimulatedTilts(double n_eff, double redundancy, int count, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> log_pixels(std::log(1000.0), std::log(50000.0)), radius(0.1, 1.0);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<NoiseSample> samples;
  for (int i = 0; i < count; ++i) {
    NoiseSample s;
    s.components = 2;
    s.pixels = std::round(std::exp(log_pixels(rng)));
    s.redundancy = redundancy;
    for (int j = 0; j < 2; ++j) {
      const double r = radius(rng);
      s.variance[j] = 0.002 * 0.002 / (s.pixels * r * r);
      const double scale = n_eff > 0.0 ? std::max(1.0, s.pixels / n_eff) : 1.0;
      s.squared[j] = std::pow(std::sqrt(redundancy * s.variance[j] * scale) * unit(rng), 2);
    }
    samples.push_back(s);
  }
  return samples;
}

TEST(BackendNoise, RecoversTheEffectiveNumberOfIndependentPixels) {
  std::mt19937_64 rng(3);
  for (const double n_eff : {10.0, 50.0, 400.0}) {
    for (const double redundancy : {1.0, 0.4}) {
      const double lambda = EstimatePixelCorrelation(SimulatedTilts(n_eff, redundancy, 2000, rng));
      ASSERT_GT(lambda, 0.0);
      // The median of 2000 draws: a few percent.
      EXPECT_NEAR(1.0 / lambda, n_eff, 0.1 * n_eff) << "redundancy " << redundancy;
    }
  }
}

TEST(BackendNoise, IndependentPixelsKeepTheFitsCovariance) {
  // Rendered frames: the errors are within the fits' covariances, so at most a few percent of
  // the median's scatter is read as correlation: the median fit's covariance grows by < 10%.
  std::mt19937_64 rng(5);
  const std::vector<NoiseSample> samples = SimulatedTilts(0.0, 0.7, 2000, rng);
  const double lambda = EstimatePixelCorrelation(samples);
  std::vector<double> pixels;
  for (const NoiseSample& s : samples) pixels.push_back(s.pixels);
  std::nth_element(pixels.begin(), pixels.begin() + pixels.size() / 2, pixels.end());
  EXPECT_LT(std::max(1.0, lambda * pixels[pixels.size() / 2]), 1.1) << "N_eff " << 1.0 / lambda;
}

// y_i = x + e_i, i = 1..n, unit weights.
struct MeanResidual {
  explicit MeanResidual(double y) : y(y) {}
  template <typename T>
  bool operator()(const T* const x, T* residual) const {
    residual[0] = x[0] - T(y);
    return true;
  }
  double y;
};

TEST(BackendNoise, RedundancyOfAMeansResidualsIsOneMinusOneOverN) {
  // The hat matrix of a mean of n is 1/n everywhere: each residual keeps (n - 1) / n of its error.
  const int n = 10;
  double x = 0.0;
  ceres::Problem problem;
  std::vector<ResidualGroup> each, all(1);
  for (int i = 0; i < n; ++i) {
    const ceres::ResidualBlockId id =
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<MeanResidual, 1, 1>(new MeanResidual(i)), nullptr, &x);
    each.push_back({{id}, 0, 1});
    all[0].blocks.push_back(id);
  }
  const std::vector<double> one = RedundancyFractions(&problem, each, 256, 1);
  ASSERT_EQ(one.size(), static_cast<size_t>(n));
  // A row's estimate scatters by sqrt(h (1 - h) / probes) = 0.019.
  for (double r : one) EXPECT_NEAR(r, 0.9, 0.08);
  const std::vector<double> whole = RedundancyFractions(&problem, all, 256, 1);
  EXPECT_NEAR(whole[0], 0.9, 0.02);
  // The same seed, the same figures.
  EXPECT_EQ(RedundancyFractions(&problem, each, 256, 1), one);
}

}  // namespace
}  // namespace planemap::backend_detail
