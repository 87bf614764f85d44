#pragma once
// The organized segmenter's per-cell sums (its hot loop), in a file of their own: see
// cell_sums.cpp for why. Internal to the frontend (and its test).
#include <cstdint>

#include <pcl/point_types.h>

namespace planemap {

// Plain sums of a cell's usable points, and whether a depth jump lies inside it.
struct CellSums {
  double n = 0, sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
  bool jump = false;  // two usable 4-neighbours in the cell differ in depth by more than jump_relative z
};

// The sums over pixels [u0, u1) x [v0, v1) of a w-wide organized cloud whose `usable` byte is
// nonzero; a jump is a usable right or lower neighbour inside the cell whose depth differs from
// the pixel's by more than jump_relative times its depth. With AVX2 where the processor has it
// (SumCellAvx2), else SumCellScalar: the same doubles either way.
CellSums SumCell(const pcl::PointXYZRGB* points, const std::uint8_t* usable, int w, int u0, int u1, int v0, int v1,
                 float jump_relative);

// The two ways of SumCell, for the test that holds them equal bit for bit. SumCellAvx2 may be
// called only if SumCellHasAvx2() (it is SumCellScalar on processors other than x86-64).
bool SumCellHasAvx2();
CellSums SumCellScalar(const pcl::PointXYZRGB* points, const std::uint8_t* usable, int w, int u0, int u1, int v0, int v1,
                       float jump_relative);
CellSums SumCellAvx2(const pcl::PointXYZRGB* points, const std::uint8_t* usable, int w, int u0, int u1, int v0, int v1,
                     float jump_relative);

}  // namespace planemap
