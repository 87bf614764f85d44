#pragma once
// Step 4 of the organized segmenter, its pixel loop (the segmenter's hottest): every usable pixel
// to the nearest of its cell's candidate planes, if near enough. Internal to the frontend (and its
// test). In a file of its own so that the loop can run with AVX2 where the processor has it,
// chosen at run time (the build targets plain x86-64), to the same result bit for bit.
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <pcl/point_types.h>

#include "planemap/core/pose.h"

namespace planemap {

// Weighted sums of a plane's points: w, x, y, z, xx, xy, xz, yy, yz, zz with w = DepthNoiseWeight(z)
// (an array, so they are added pairwise in vector registers).
using WeightedSums = Eigen::Array<double, 10, 1>;

// A distance limit that grows with depth as a depth sensor's noise does: base + quadratic z^2 [m].
// The inlier limit of step 4, and the segmenter's other limits (organized_segmenter.cpp); the
// order of the operations is part of the bit-for-bit agreement of the scalar and AVX2 loops.
inline double GrowsWithDepth(double base, double quadratic, double z) { return base + quadratic * z * z; }

// A plane a cell's pixels may go to: n.p + d = 0, and the region it is.
struct AssignCandidate {
  double nx, ny, nz, d;
  int region;
};

// Where the pixels go. Region r's: its inliers (pixel indices, appended in row order), the
// weighted sums and count of those that pull on its refit, and the box of all of them, at
// inliers[r], sums[r], count[r], bounds[r]. A pixel close enough to two planes is marked in
// ambiguous (indexed by pixel) and pulls on no refit.
struct AssignOutput {
  std::vector<int>* inliers = nullptr;
  WeightedSums* sums = nullptr;
  double* count = nullptr;
  Box3* bounds = nullptr;
  std::uint8_t* ambiguous = nullptr;
};

// The grid: cells of cs x cs pixels, cw to a row, over a w x h organized cloud; cell i's
// candidates are candidates[first[i]] .. candidates[first[i + 1] - 1]. A pixel is an inlier of a
// plane when |n.p + d| < inlier_base + inlier_quadratic z^2.
struct AssignGrid {
  const pcl::PointXYZRGB* points = nullptr;
  const std::uint8_t* usable = nullptr;
  int w = 0, h = 0, cs = 1, cw = 0;
  const AssignCandidate* candidates = nullptr;
  const int* first = nullptr;
  double inlier_base = 0.0, inlier_quadratic = 0.0;
};

// Each usable pixel, in row order, to the nearest candidate of its cell within its inlier
// distance (AVX2 where the processor has it, else the scalar loop: the same result).
void AssignPixels(const AssignGrid& grid, const AssignOutput& out);

// The two ways of AssignPixels, for the test that holds them equal bit for bit.
// AssignPixelsAvx2 may be called only if AssignPixelsHasAvx2() (it is the scalar loop on
// processors other than x86-64).
bool AssignPixelsHasAvx2();
void AssignPixelsScalar(const AssignGrid& grid, const AssignOutput& out);
void AssignPixelsAvx2(const AssignGrid& grid, const AssignOutput& out);

}  // namespace planemap
