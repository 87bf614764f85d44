// The back end's uncertainty against its errors (the NEES study of `planemap nees`) on a small
// set of seeded runs, and the chi-square quantiles its interval comes from.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "planemap/apps/consistency.h"

namespace planemap {
namespace {

TEST(Consistency, ChiSquareQuantilesMatchTheTables) {
  // Tabulated chi-square quantiles (Abramowitz and Stegun, table 26.8).
  EXPECT_NEAR(ChiSquareQuantile(0.975, 10), 20.483, 5e-4);
  EXPECT_NEAR(ChiSquareQuantile(0.025, 10), 3.247, 5e-4);
  EXPECT_NEAR(ChiSquareQuantile(0.975, 100), 129.561, 5e-4);
  EXPECT_NEAR(ChiSquareQuantile(0.025, 100), 74.222, 5e-4);
}

// Four seeded renderings of the default walk (the full study is `planemap nees --runs 50`): the
// box is refined with every dimension measured in each, each dimension's error lies within three
// of its standard deviations, and the covariances are not optimistic (the average NEES per degree
// of freedom is not above the chi-square interval).
TEST(Consistency, BoxDimensionCovariancesAreNotOptimisticOnSeededRuns) {
  ConsistencyOptions options;
  options.runs = 4;
  options.threads = 2;
  const ConsistencyResult r = RunConsistencyStudy(options);
  EXPECT_EQ(r.missing, 0);
  ASSERT_EQ(r.runs.size(), 4u);
  for (const ConsistencyRun& run : r.runs) {
    std::printf("seed %d: %s errors %+.2f %+.2f %+.2f mm, std %.2f %.2f %.2f mm, NEES %.2f\n", run.seed, run.object.c_str(),
                1000 * run.error.x(), 1000 * run.error.y(), 1000 * run.error.z(), 1000 * run.std.x(), 1000 * run.std.y(),
                1000 * run.std.z(), run.nees);
    EXPECT_EQ(run.dof, 3);
    for (int k = 0; k < 3; ++k) EXPECT_LE(std::abs(run.error[k]), 3.0 * run.std[k]) << "m, seed " << run.seed << " axis " << k;
  }
  std::printf("ANEES %.2f over %d dof, 95%% interval [%.2f, %.2f]\n", r.anees, r.dof, r.low, r.high);
  EXPECT_LE(r.anees, r.high);
}

}  // namespace
}  // namespace planemap
