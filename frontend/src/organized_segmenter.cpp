#include "planemap/frontend/organized_segmenter.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <numeric>
#include <queue>
#include <limits>
#include <optional>
#include <random>

#include <Eigen/Eigenvalues>

#include "assign_pixels.h"
#include "cell_sums.h"

namespace planemap {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// A plane fitted to moments, oriented toward the camera; fast closed-form eigen solve.
struct QuickFit {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double offset = 0.0;
  double mse = 0.0;  // mean squared distance to the plane [m^2]
};

QuickFit Fit(const PointMoments& m) {
  QuickFit f;
  f.centroid = m.Mean();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(m.Covariance());
  f.normal = eig.eigenvectors().col(0);
  f.mse = std::max(eig.eigenvalues()(0), 0.0);
  if (f.normal.dot(f.centroid) > 0.0) f.normal = -f.normal;
  f.offset = -f.normal.dot(f.centroid);
  return f;
}

struct Cell {
  PointMoments moments;
  QuickFit fit;
  bool planar = false;
  int region = -1;
};

struct Region {
  PointMoments moments;
  QuickFit fit;
  int cells = 0;
};

// The moments of `n` points from their weighted sums.
PointMoments MomentsOf(const WeightedSums& s, double n) {
  PointMoments m;
  m.n = n;
  m.w = s[0];
  m.sum = Eigen::Vector3d(s[1], s[2], s[3]);
  m.sum_outer << s[4], s[5], s[6], s[5], s[7], s[8], s[6], s[8], s[9];
  return m;
}

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Regions grown on a grid of cells over the usable pixels (steps 1-3).
struct Pass {
  int cs = 0, cw = 0, ch = 0;
  std::vector<Cell> cells;      // cells[i].region: index into regions, or < 0
  std::vector<Region> regions;  // merged regions
};

Pass GrowPass(const Cloud& cloud, const std::vector<std::uint8_t>& usable, int cell_size, bool first_pass,
              const OrganizedSegmenterConfig& c) {
  const int w = static_cast<int>(cloud.width), h = static_cast<int>(cloud.height), cs = cell_size;
  const int cw = (w + cs - 1) / cs, ch = (h + cs - 1) / cs;
  const pcl::PointXYZRGB* const points = cloud.points.data();
  const float jump_relative = static_cast<float>(c.cell_jump_relative);
  Pass pass;
  pass.cs = cs;
  pass.cw = cw;
  pass.ch = ch;
  std::vector<Cell>& cells = pass.cells;
  cells.resize(static_cast<size_t>(cw) * ch);

  // Usable pixels per cell, counted in one sweep: cells too empty are skipped unread. The first
  // pass (every valid pixel usable) needs no count: its cells are read anyway.
  std::vector<int> usable_count(cells.size(), cs * cs);
  if (!first_pass) std::fill(usable_count.begin(), usable_count.end(), 0);
  for (int v = 0; v < h && !first_pass; ++v) {
    const std::uint8_t* row = &usable[static_cast<size_t>(v) * w];
    int* counts = &usable_count[static_cast<size_t>(v / cs) * cw];
    for (int cx = 0, u = 0; cx < cw; ++cx) {
      // Eight mask bytes (each 0 or 1) at a time: multiplied by 0x0101...01, their sum (at most
      // 8, no carry between bytes) lands in the top byte. Summed in a local: the mask's bytes may
      // alias the counts, as far as the compiler knows.
      int count = 0;
      const int end = std::min(w, u + cs);
      for (std::uint64_t eight = 0; u + 8 <= end; u += 8) {
        std::memcpy(&eight, row + u, 8);
        count += static_cast<int>((eight * 0x0101010101010101ULL) >> 56);
      }
      for (; u < end; ++u) count += row[u];
      counts[cx] += count;
    }
  }

  // 1. Fit a plane to every cell that is full enough and free of depth jumps.
  for (int cy = 0; cy < ch; ++cy) {
    for (int cx = 0; cx < cw; ++cx) {
      Cell& cell = cells[static_cast<size_t>(cy) * cw + cx];
      const int u0 = cx * cs, v0 = cy * cs, u1 = std::min(w, u0 + cs), v1 = std::min(h, v0 + cs);
      if (usable_count[static_cast<size_t>(cy) * cw + cx] < c.min_cell_valid_fraction * (u1 - u0) * (v1 - v0)) continue;
      // Plain sums of the cell's points (the hot loop of the segmenter), then moments.
      const CellSums sums = SumCell(points, usable.data(), w, u0, u1, v0, v1, jump_relative);
      cell.moments.n = cell.moments.w = sums.n;
      cell.moments.sum = Eigen::Vector3d(sums.sx, sums.sy, sums.sz);
      cell.moments.sum_outer << sums.sxx, sums.sxy, sums.sxz, sums.sxy, sums.syy, sums.syz, sums.sxz, sums.syz, sums.szz;
      if (sums.jump || cell.moments.n < c.min_cell_valid_fraction * (u1 - u0) * (v1 - v0) || cell.moments.n < 3) continue;
      cell.fit = Fit(cell.moments);
      const double z = cell.fit.centroid.z();
      cell.planar = std::sqrt(cell.fit.mse) < GrowsWithDepth(c.cell_max_rms_base, c.cell_max_rms_quadratic, z);
    }
  }

  // 2. Grow regions from the flattest cells: a neighbour joins when its normal and centroid
  //    agree with the region's plane, refitted as it grows.
  std::vector<int> order;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (cells[i].planar) order.push_back(static_cast<int>(i));
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return cells[a].fit.mse < cells[b].fit.mse; });
  std::vector<Region> regions;
  std::vector<int> members;
  for (int seed : order) {
    if (cells[seed].region >= 0) continue;
    const int id = static_cast<int>(regions.size());
    Region region{cells[seed].moments, cells[seed].fit, 1};
    cells[seed].region = id;
    members.assign(1, seed);
    std::queue<int> queue;
    queue.push(seed);
    while (!queue.empty()) {
      const int i = queue.front();
      queue.pop();
      const int cx = i % cw, cy = i / cw;
      const int neighbours[4][2] = {{cx + 1, cy}, {cx - 1, cy}, {cx, cy + 1}, {cx, cy - 1}};
      for (const auto& nb : neighbours) {
        if (nb[0] < 0 || nb[0] >= cw || nb[1] < 0 || nb[1] >= ch) continue;
        const int j = nb[1] * cw + nb[0];
        Cell& cell = cells[j];
        if (!cell.planar || cell.region >= 0) continue;
        const double z = cell.fit.centroid.z();
        const double max_angle = (c.grow_max_angle_deg + c.grow_max_angle_deg_per_m * z) * kDegToRad;
        if (cell.fit.normal.dot(region.fit.normal) < std::cos(max_angle)) continue;
        const double distance = std::abs(region.fit.normal.dot(cell.fit.centroid) + region.fit.offset);
        if (distance > GrowsWithDepth(c.grow_max_distance_base, c.grow_max_distance_quadratic, z)) continue;
        cell.region = id;
        members.push_back(j);
        region.moments += cell.moments;
        region.fit = Fit(region.moments);
        ++region.cells;
        queue.push(j);
      }
    }
    if (region.cells < c.min_region_cells) {
      for (int i : members) cells[i].region = -2;  // too small: never a seed again, never joined
      continue;
    }
    regions.push_back(region);
  }

  // 3. Merge adjacent regions that lie in one plane (growing can split a plane at a noisy cell).
  std::vector<int> parent(regions.size());
  std::iota(parent.begin(), parent.end(), 0);
  const double cos_merge = std::cos(c.merge_max_angle_deg * kDegToRad);
  auto coplanar = [&](const Region& a, const Region& b) {
    if (a.fit.normal.dot(b.fit.normal) < cos_merge) return false;
    const double za = a.fit.centroid.z(), zb = b.fit.centroid.z();
    return std::abs(a.fit.normal.dot(b.fit.centroid) + a.fit.offset) <
               GrowsWithDepth(c.grow_max_distance_base, c.grow_max_distance_quadratic, zb) &&
           std::abs(b.fit.normal.dot(a.fit.centroid) + b.fit.offset) <
               GrowsWithDepth(c.grow_max_distance_base, c.grow_max_distance_quadratic, za);
  };
  for (int cy = 0; cy < ch; ++cy) {
    for (int cx = 0; cx < cw; ++cx) {
      const int a = cells[cy * cw + cx].region;
      if (a < 0) continue;
      for (const int j : {cx + 1 < cw ? cy * cw + cx + 1 : -1, cy + 1 < ch ? (cy + 1) * cw + cx : -1}) {
        if (j < 0 || cells[j].region < 0) continue;
        const int ra = Find(parent, a), rb = Find(parent, cells[j].region);
        if (ra != rb && coplanar(regions[ra], regions[rb])) parent[std::max(ra, rb)] = std::min(ra, rb);
      }
    }
  }
  std::vector<int> root_index(regions.size(), -1);
  std::vector<Region> merged;
  for (size_t r = 0; r < regions.size(); ++r) {
    const int root = Find(parent, static_cast<int>(r));
    if (root_index[root] < 0) {
      root_index[root] = static_cast<int>(merged.size());
      merged.push_back(Region{});
    }
    merged[root_index[root]].moments += regions[r].moments;
  }
  for (Region& r : merged) r.fit = Fit(r.moments);
  for (Cell& cell : cells) cell.region = cell.region >= 0 ? root_index[Find(parent, cell.region)] : -1;
  pass.regions = std::move(merged);
  return pass;
}


// Step 4 on one pass: every usable pixel goes to the nearest plane among those of its cell and
// the 8 cells around it, if it is close enough: this takes back the pixels of edge and corner
// cells. Pixels are visited in row order, so each plane's inliers come out sorted. A pixel close
// enough to two planes (near their intersection, where the noise decides which is nearer) stays
// an inlier of the nearer one but does not pull on its refit. Inliers of region r go to
// (*inliers)[offset + r].
void AssignPass(const Cloud& cloud, const std::vector<std::uint8_t>& usable, const Pass& pass,
                const OrganizedSegmenterConfig& c, size_t offset, std::vector<std::vector<int>>* inliers,
                std::vector<WeightedSums>* sums, std::vector<double>* fit_count,
                std::vector<Box3>* bounds, std::vector<std::uint8_t>* ambiguous) {
  const int w = static_cast<int>(cloud.width), h = static_cast<int>(cloud.height);
  const int cs = pass.cs, cw = pass.cw, ch = pass.ch;
  const std::vector<Cell>& cells = pass.cells;
  const std::vector<Region>& merged = pass.regions;
  // Each cell's candidate planes side by side (cell i's are [first[i], first[i + 1])), so the
  // pixel loop reads them without going through the regions.
  std::vector<AssignCandidate> candidates;
  std::vector<int> first(cells.size() + 1, 0);
  for (int cy = 0; cy < ch; ++cy) {
    for (int cx = 0; cx < cw; ++cx) {
      const int i = cy * cw + cx;
      first[i] = static_cast<int>(candidates.size());
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = cx + dx, y = cy + dy;
          if (x < 0 || x >= cw || y < 0 || y >= ch) continue;
          const int r = cells[y * cw + x].region;
          if (r < 0) continue;
          const auto known = std::find_if(candidates.begin() + first[i], candidates.end(),
                                          [r](const AssignCandidate& k) { return k.region == r; });
          if (known != candidates.end()) continue;
          const QuickFit& f = merged[r].fit;
          candidates.push_back({f.normal.x(), f.normal.y(), f.normal.z(), f.offset, r});
        }
      }
    }
  }
  first[cells.size()] = static_cast<int>(candidates.size());
  // Room for as many inliers as a region's cells hold pixels (it takes most of them, and more
  // from the cells around): spares the vector's doublings on the way there.
  for (size_t r = 0; r < merged.size(); ++r) (*inliers)[offset + r].reserve(static_cast<size_t>(merged[r].moments.n));
  AssignGrid grid;
  grid.points = cloud.points.data();
  grid.usable = usable.data();
  grid.w = w, grid.h = h, grid.cs = cs, grid.cw = cw;
  grid.candidates = candidates.data();
  grid.first = first.data();
  grid.inlier_base = c.inlier_distance_base, grid.inlier_quadratic = c.inlier_distance_quadratic;
  AssignOutput to;
  to.inliers = inliers->data() + offset;
  to.sums = sums->data() + offset;
  to.count = fit_count->data() + offset;
  to.bounds = bounds->data() + offset;
  to.ambiguous = ambiguous->data();
  AssignPixels(grid, to);
}

// A pixel's inlier distance at depth z [m].
double InlierDistance(const OrganizedSegmenterConfig& c, double z) {
  return GrowsWithDepth(c.inlier_distance_base, c.inlier_distance_quadratic, z);
}

// |n.p + d| [m].
double PlaneDistance(const Eigen::Vector3d& n, double d, const pcl::PointXYZRGB& p) {
  return std::abs(n.x() * p.x + n.y() * p.y + n.z() * p.z + d);
}

// MSAC's truncated squared loss of the plane n.p + d = 0 on every stride-th of `pixels`, the
// distances over half the inlier distance (the sample consensus of steps 4b and 5).
double TruncatedCost(const Cloud& cloud, const std::vector<int>& pixels, size_t stride, const Eigen::Vector3d& n,
                     double d, const OrganizedSegmenterConfig& c) {
  double cost = 0.0;
  for (size_t k = 0; k < pixels.size(); k += stride) {
    const pcl::PointXYZRGB& p = cloud[pixels[k]];
    const double r = PlaneDistance(n, d, p) / (0.5 * InlierDistance(c, p.z));
    cost += std::min(1.0, r * r);
  }
  return cost;
}

// The plane through three of `pixels` drawn by `pick`; nothing when they are on one line.
std::optional<Plane> PlaneThroughThree(const Cloud& cloud, const std::vector<int>& pixels,
                                       std::uniform_int_distribution<size_t>& pick, std::mt19937& random) {
  const Eigen::Vector3d a = cloud[pixels[pick(random)]].getVector3fMap().cast<double>();
  const Eigen::Vector3d b = cloud[pixels[pick(random)]].getVector3fMap().cast<double>();
  const Eigen::Vector3d e = cloud[pixels[pick(random)]].getVector3fMap().cast<double>();
  Eigen::Vector3d n = (b - a).cross(e - a);
  if (n.norm() < 1e-9) return std::nullopt;
  n.normalize();
  return Plane{n, -n.dot(a)};
}

// Step 5's check, for a plane robust_min_depth or farther: the share of its inliers farther than
// half the inlier distance from it. Above robust_check_share, the plane most of them lie on by
// sample consensus (MSAC's truncated squared loss on distances over half the inlier distance, as
// the check), refitted on those within the inlier distance of it; the rest are dropped. Nothing:
// the plane stands as it is (also when the least-squares plane itself scores best).
std::optional<std::vector<int>> RobustInliers(const Cloud& cloud, const std::vector<int>& inliers, const PlaneFit& fit,
                               const OrganizedSegmenterConfig& c, std::uint32_t seed) {
  const auto limit = [&](const pcl::PointXYZRGB& p) { return InlierDistance(c, p.z); };
  if (fit.centroid.z() < c.robust_min_depth) return std::nullopt;
  // The share from at most 2000 of them, and at most 300 scored per hypothesis.
  int far = 0, checked = 0;
  for (size_t k = 0; k < inliers.size(); k += std::max<size_t>(1, inliers.size() / 2000), ++checked) {
    far += PlaneDistance(fit.plane.normal, fit.plane.offset, cloud[inliers[k]]) > 0.5 * limit(cloud[inliers[k]]);
  }
  if (far <= c.robust_check_share * checked) return std::nullopt;
  const size_t stride = std::max<size_t>(1, inliers.size() / 300);
  std::mt19937 random(seed);
  std::uniform_int_distribution<size_t> pick(0, inliers.size() - 1);
  Eigen::Vector3d best_normal = fit.plane.normal;
  double best_offset = fit.plane.offset, best_cost = std::numeric_limits<double>::infinity();
  int best_hypothesis = 0;
  for (int h = 0; h <= c.robust_hypotheses; ++h) {
    Plane hypothesis = fit.plane;  // hypothesis 0: the least-squares plane itself
    if (h > 0) {
      const std::optional<Plane> drawn = PlaneThroughThree(cloud, inliers, pick, random);
      if (!drawn) continue;
      hypothesis = *drawn;
    }
    const double cost = TruncatedCost(cloud, inliers, stride, hypothesis.normal, hypothesis.offset, c);
    if (cost < best_cost) {
      best_cost = cost;
      best_normal = hypothesis.normal;
      best_offset = hypothesis.offset;
      best_hypothesis = h;
    }
  }
  if (best_hypothesis == 0) return std::nullopt;  // most of them lie on the least-squares plane
  std::vector<int> kept;
  for (int i : inliers) {
    if (PlaneDistance(best_normal, best_offset, cloud[i]) < limit(cloud[i])) kept.push_back(i);
  }
  return kept;
}

// The pixels reached from `seed` on the cloud's grid through 4 neighbours (8 if `diagonal`) that
// `joins(from, to)` takes (it marks them), into *reached; the seed is taken by the caller. A
// neighbour without depth is looked past, up to `bridge` pixels on in the same direction. The
// stack holds each pixel's column and row: no division per pixel to find them.
template <class Joins>
void Flood(int seed, const Cloud& cloud, bool diagonal, int bridge, std::vector<int>* stack, std::vector<int>* reached,
           Joins joins) {
  const int w = static_cast<int>(cloud.width), h = static_cast<int>(cloud.height);
  reached->clear();
  stack->assign({seed % w, seed / w});
  while (!stack->empty()) {
    const int v = stack->back();
    stack->pop_back();
    const int u = stack->back();
    stack->pop_back();
    const int i = v * w + u;
    reached->push_back(i);
    for (int dv = -1; dv <= 1; ++dv) {
      for (int du = -1; du <= 1; ++du) {
        if ((du == 0 && dv == 0) || (!diagonal && du != 0 && dv != 0)) continue;
        // The neighbour that way; past up to `bridge` pixels without depth.
        for (int step = 1; step <= bridge + 1; ++step) {
          const int uu = u + step * du, vv = v + step * dv;
          if (uu < 0 || uu >= w || vv < 0 || vv >= h) break;
          const int j = vv * w + uu;
          if (step <= bridge && !IsValidPoint(cloud[j])) continue;
          if (joins(i, j)) {
            stack->push_back(uu);
            stack->push_back(vv);
          }
          break;
        }
      }
    }
  }
}

// Sorts the pixels of a part, each marked `mark` in `marks` (as other pixels may be), none before
// `first`: a compact part (a strip along a few rows) is collected by scanning the span of pixel
// indices it covers, faster than sorting; a sparse one is sorted. Either way the part comes out
// in ascending order and the marks as they were.
void SortPixels(int first, std::uint8_t mark, std::vector<int>* part, std::vector<std::uint8_t>* marks) {
  const int last = *std::max_element(part->begin(), part->end());
  if (static_cast<size_t>(last - first) > 16 * part->size()) {
    std::sort(part->begin(), part->end());
    return;
  }
  constexpr std::uint8_t kCollecting = 255;  // the part's own pixels while they are collected
  for (const int i : *part) (*marks)[i] = kCollecting;
  part->clear();
  for (int i = first; i <= last; ++i) {
    if ((*marks)[i] != kCollecting) continue;
    (*marks)[i] = mark;
    part->push_back(i);
  }
}

// Step 4b: planes among the pixels no plane took, where no cell fits (a box's side seen as a
// strip 10-18 px wide running diagonally across the image). The free pixels are split into parts
// connected on the image grid (across up to `bridge` pixels without depth) without a depth
// jump; in each part of min_inliers pixels or more,
// sample consensus (leftover_hypotheses planes through 3 of its pixels, MSAC's truncated loss at
// half the inlier distance, the best refitted by least squares on the pixels it holds) finds the
// plane most of them lie on, whose pixels within the inlier distance make a plane if they are
// min_inliers or more and connected (as the parts are); then again on the part's remaining pixels.
std::vector<std::vector<int>> LeftoverPlanes(const Cloud& cloud, const std::vector<std::uint8_t>& usable,
                                             const OrganizedSegmenterConfig& c, int min_inliers, int bridge) {
  const int w = static_cast<int>(cloud.width), h = static_cast<int>(cloud.height);
  const auto limit = [&](const pcl::PointXYZRGB& p) { return InlierDistance(c, p.z); };
  std::vector<std::uint8_t> in_part(usable.size(), 0);  // taken by a part already
  std::vector<std::uint8_t> in_plane(usable.size(), 0);  // 1: on the plane being split, 2: visited
  std::vector<std::vector<int>> found;
  std::vector<int> stack, part;  // part: its memory kept from part to part
  std::mt19937 random(static_cast<std::uint32_t>(c.robust_seed));
  for (int start = 0; start < w * h; ++start) {
    // Most pixels are taken: skip them 8 at a time.
    for (std::uint64_t eight = 0; start + 8 <= w * h; start += 8) {
      std::memcpy(&eight, &usable[start], 8);
      if (eight != 0) break;
    }
    if (start == w * h) break;  // all taken to the end
    if (!usable[start] || in_part[start]) continue;
    in_part[start] = 1;
    Flood(start, cloud, false, bridge, &stack, &part, [&](int i, int j) {
      if (!usable[j] || in_part[j] || std::abs(cloud[j].z - cloud[i].z) > static_cast<float>(c.cell_jump_relative) * cloud[i].z) {
        return false;
      }
      in_part[j] = 1;
      return true;
    });
    if (static_cast<int>(part.size()) < min_inliers) continue;  // most parts: a few pixels
    SortPixels(start, 1, &part, &in_part);  // row order: the samples do not hang on the fill's order
    while (static_cast<int>(part.size()) >= min_inliers) {
      const size_t stride = std::max<size_t>(1, part.size() / 250);
      std::uniform_int_distribution<size_t> pick(0, part.size() - 1);
      Eigen::Vector3d best_normal = Eigen::Vector3d::UnitZ();
      double best_offset = 0.0, best_cost = std::numeric_limits<double>::infinity();
      for (int hypothesis = 0; hypothesis < c.leftover_hypotheses; ++hypothesis) {
        const std::optional<Plane> drawn = PlaneThroughThree(cloud, part, pick, random);
        if (!drawn) continue;
        const double cost = TruncatedCost(cloud, part, stride, drawn->normal, drawn->offset, c);
        if (cost < best_cost) {
          best_cost = cost;
          best_normal = drawn->normal;
          best_offset = drawn->offset;
        }
      }
      if (!std::isfinite(best_cost)) break;
      PointMoments held;
      for (size_t k = 0; k < part.size(); k += stride) {
        const pcl::PointXYZRGB& p = cloud[part[k]];
        if (PlaneDistance(best_normal, best_offset, p) < 0.5 * limit(p)) held.Add(p.getVector3fMap().cast<double>(), DepthNoiseWeight(p.z));
      }
      const PlaneFit refit = FitPlane(held);
      if (refit.ok && TruncatedCost(cloud, part, stride, refit.plane.normal, refit.plane.offset, c) < best_cost) {
        best_normal = refit.plane.normal;
        best_offset = refit.plane.offset;
      }
      std::vector<int> on, rest;
      for (int i : part) (PlaneDistance(best_normal, best_offset, cloud[i]) < limit(cloud[i]) ? on : rest).push_back(i);
      if (static_cast<int>(on.size()) < min_inliers) break;
      // Its pixels connected on the image grid (8-neighbours) make a plane each, if enough.
      for (int i : on) in_plane[i] = 1;
      for (int seed : on) {
        if (in_plane[seed] != 1) continue;
        in_plane[seed] = 2;
        std::vector<int> piece;
        Flood(seed, cloud, true, bridge, &stack, &piece, [&](int, int j) {
          if (in_plane[j] != 1) return false;
          in_plane[j] = 2;
          return true;
        });
        if (static_cast<int>(piece.size()) < min_inliers) continue;
        SortPixels(seed, 2, &piece, &in_plane);  // `on` is sorted: no pixel of the piece before its seed
        found.push_back(std::move(piece));
      }
      for (int i : on) in_plane[i] = 0;
      part = std::move(rest);
    }
  }
  return found;
}

// Step 4c: a strip (step 4b) takes back the pixels beside it that lie on it rather than on the
// plane that took them in step 4, where no plane for the strip's face existed yet (the ledge of a
// box's top beside the box stacked on it took the lower rows of that box's side, a few
// millimetres from its plane, and came out 13.6 deg off level). From each strip's pixels, through
// 8-neighbours: a pixel of a plane joins the strip when it lies off that plane by half the inlier
// distance or more and within half of it of the strip's plane (as found: refitted on what it
// takes, a strip could creep over a face), the two planes strip_take_back_min_angle_deg or more
// from parallel. Only planes nearer than robust_min_depth give pixels back: farther, the
// consensus check of step 5 cleans a plane, and a plane partly cleaned here could slip under it.
// The planes that lost pixels are refitted on their unambiguous pixels (step 4's, less those
// taken), which brings more of the strip's face off them: up to strip_take_back_rounds rounds.
void StripsTakeBack(const Cloud& cloud, const OrganizedSegmenterConfig& c, const std::vector<std::uint8_t>& ambiguous,
                    int min_inliers, std::vector<std::vector<int>>* inliers, std::vector<PointMoments>* fit_moments,
                    std::vector<Box3>* bounds, std::vector<std::vector<int>>* strips) {
  if (strips->empty() || c.strip_take_back_rounds <= 0) return;
  const int w = static_cast<int>(cloud.width), h = static_cast<int>(cloud.height);
  const int regions = static_cast<int>(inliers->size());
  // Kept, and nearer than robust_min_depth (no consensus check): may give pixels back.
  std::vector<Plane> region_plane(regions);
  std::vector<std::uint8_t> near(regions, 0);
  for (int r = 0; r < regions; ++r) {
    if (static_cast<int>((*inliers)[r].size()) < min_inliers) continue;
    const PlaneFit fit = FitPlane((*fit_moments)[r]);
    region_plane[r] = fit.plane;
    near[r] = fit.ok && fit.centroid.z() < c.robust_min_depth;
  }
  // Whose each pixel is (region r, or regions + strip s), in the window the strips grow in: their
  // pixel box and cell_size pixels around it.
  int u0 = w, u1 = -1, v0 = h, v1 = -1;
  for (const std::vector<int>& strip : *strips) {
    for (int i : strip) u0 = std::min(u0, i % w), u1 = std::max(u1, i % w);
    v0 = std::min(v0, strip.front() / w), v1 = std::max(v1, strip.back() / w);
  }
  const int margin = c.cell_size;
  u0 = std::max(0, u0 - margin), u1 = std::min(w - 1, u1 + margin);
  v0 = std::max(0, v0 - margin), v1 = std::min(h - 1, v1 + margin);
  const int ww = u1 - u0 + 1;
  std::vector<int> owner(static_cast<size_t>(ww) * (v1 - v0 + 1), -1);
  auto local = [&](int i) { return (i / w - v0) * ww + (i % w - u0); };
  for (int r = 0; r < regions; ++r) {
    if (!near[r]) continue;
    const std::vector<int>& pixels = (*inliers)[r];
    auto it = pixels.begin();
    for (int v = v0; v <= v1 && it != pixels.end(); ++v) {  // sorted: each row's stretch in the window
      it = std::lower_bound(it, pixels.end(), v * w + u0);
      for (const int end = v * w + u1; it != pixels.end() && *it <= end; ++it) owner[local(*it)] = r;
    }
  }
  for (size_t s = 0; s < strips->size(); ++s) {
    for (int i : (*strips)[s]) owner[local(i)] = regions + static_cast<int>(s);
  }
  std::vector<Plane> strip_plane;  // as found (refitted on what they take, they could creep)
  for (const std::vector<int>& strip : *strips) strip_plane.push_back(FitDetectedPlane(cloud, strip).plane);
  const double max_cos = std::cos(c.strip_take_back_min_angle_deg * kDegToRad);
  std::vector<int> stack;
  for (int round = 0; round < c.strip_take_back_rounds; ++round) {
    std::vector<std::vector<int>> lost(regions);  // the pixels each region lost this round
    bool taken = false;
    for (size_t s = 0; s < strips->size(); ++s) {
      std::vector<int>& strip = (*strips)[s];
      const Plane& plane = strip_plane[s];
      const int id = regions + static_cast<int>(s);
      stack = strip;
      while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        const int u = i % w, v = i / w;
        for (int dv = -1; dv <= 1; ++dv) {
          for (int du = -1; du <= 1; ++du) {
            const int uu = u + du, vv = v + dv;
            if (uu < u0 || uu > u1 || vv < v0 || vv > v1) continue;
            const int j = vv * w + uu;
            const int r = owner[local(j)];
            if (r < 0 || r >= regions || std::abs(region_plane[r].normal.dot(plane.normal)) > max_cos) continue;
            const pcl::PointXYZRGB& p = cloud[j];
            const Eigen::Vector3d x(p.x, p.y, p.z);
            const double limit = InlierDistance(c, p.z);
            const double d_own = std::abs(region_plane[r].SignedDistance(x)), d_strip = std::abs(plane.SignedDistance(x));
            if (d_own < 0.5 * limit || d_strip >= 0.5 * limit) continue;
            lost[r].push_back(j);
            owner[local(j)] = id;
            strip.push_back(j);
            stack.push_back(j);
            taken = true;
            if (ambiguous[j]) continue;
            PointMoments& m = (*fit_moments)[r];  // j no longer pulls on r's refit
            const double weight = DepthNoiseWeight(p.z);
            m.n -= 1.0;
            m.w -= weight;
            m.sum -= weight * x;
            m.sum_outer -= weight * x * x.transpose();
          }
        }
      }
      std::sort(strip.begin(), strip.end());
    }
    if (!taken) break;
    for (int r = 0; r < regions; ++r) {
      std::vector<int>& gone = lost[r];
      if (gone.empty()) continue;
      // Both sorted: one pass over the stretch of r's pixels the lost ones lie in.
      std::sort(gone.begin(), gone.end());
      std::vector<int>& pixels = (*inliers)[r];
      const auto first = std::lower_bound(pixels.begin(), pixels.end(), gone.front());
      const auto last = std::upper_bound(first, pixels.end(), gone.back());
      auto out = first;
      size_t k = 0;
      for (auto it = first; it != last; ++it) {
        while (k < gone.size() && gone[k] < *it) ++k;
        if (k == gone.size() || gone[k] != *it) *out++ = *it;
      }
      pixels.erase(out, last);
      // The box of r's points stays unless a lost point was on it; then it is computed again
      // from the inliers when needed.
      Box3& box = (*bounds)[r];
      for (int i : gone) {
        const Eigen::Vector3d x(cloud[i].x, cloud[i].y, cloud[i].z);
        if ((x.array() == box.low.array()).any() || (x.array() == box.high.array()).any()) box = Box3{};
      }
      const PlaneFit fit = FitPlane((*fit_moments)[r]);
      if (fit.ok) region_plane[r] = fit.plane;
    }
  }
}

}  // namespace

SegmentationResult OrganizedSegmenter::Segment(const Cloud& cloud) const {
  const OrganizedSegmenterConfig& c = config_.organized;
  std::vector<std::uint8_t> usable(cloud.size());
  int valid_points = 0;
  for (size_t i = 0; i < cloud.size(); ++i) valid_points += usable[i] = IsValidPoint(cloud[i]);

  // Two passes: cells of cell_size, then cells half as large over the pixels the first left
  // (small faces: thin panels, a box top seen at a grazing angle).
  std::vector<std::vector<int>> inliers;
  std::vector<WeightedSums> sums;
  std::vector<double> fit_count;
  std::vector<Box3> bounds;  // of each region's inliers
  std::vector<std::uint8_t> ambiguous(cloud.size(), 0);  // close to two planes: pulls on no refit
  for (const int cell_size : {c.cell_size, std::max(4, c.cell_size / 2)}) {
    const Pass pass = GrowPass(cloud, usable, cell_size, cell_size == c.cell_size, c);
    const size_t offset = inliers.size();
    inliers.resize(offset + pass.regions.size());
    sums.resize(inliers.size(), WeightedSums::Zero());
    fit_count.resize(inliers.size(), 0.0);
    bounds.resize(inliers.size());
    AssignPass(cloud, usable, pass, c, offset, &inliers, &sums, &fit_count, &bounds, &ambiguous);
    for (size_t r = offset; r < inliers.size(); ++r) {  // kept planes' pixels are taken
      if (static_cast<int>(inliers[r].size()) < config_.min_inliers) continue;
      for (int i : inliers[r]) usable[i] = 0;
    }
  }
  std::vector<std::vector<int>> leftover;
  if (c.leftover_hypotheses > 0) leftover = LeftoverPlanes(cloud, usable, c, config_.min_inliers, 0);
  // Then on the pixels still free, parts joined across pixels without depth (a narrow face cut
  // by dropouts into pieces each too small). Those strips take no pixels back (below): letting
  // them took the TUM fr1_rpy slice's tracking ATE from 35.8 to 75.0 mm.
  std::vector<std::vector<int>> bridged;
  if (c.leftover_hypotheses > 0 && c.leftover_bridge_px > 0) {
    for (const std::vector<int>& strip : leftover) {
      for (int i : strip) usable[i] = 0;
    }
    bridged = LeftoverPlanes(cloud, usable, c, config_.min_inliers, c.leftover_bridge_px);
  }
  std::vector<PointMoments> fit_moments(inliers.size());
  for (size_t r = 0; r < inliers.size(); ++r) {
    fit_moments[r] = MomentsOf(sums[r], fit_count[r]);
  }

  StripsTakeBack(cloud, c, ambiguous, config_.min_inliers, &inliers, &fit_moments, &bounds, &leftover);
  leftover.insert(leftover.end(), std::make_move_iterator(bridged.begin()), std::make_move_iterator(bridged.end()));

  // 5. Least-squares refit on each plane's unambiguous inliers.
  std::vector<DetectedPlane> planes;
  for (size_t r = 0; r < inliers.size(); ++r) {
    if (static_cast<int>(inliers[r].size()) < config_.min_inliers) continue;
    const PlaneFit fit = FitPlane(fit_moments[r]);
    if (!fit.ok || fit_moments[r].n < 0.5 * inliers[r].size()) {
      planes.push_back(FitDetectedPlane(cloud, std::move(inliers[r])));
      continue;
    }
    std::optional<std::vector<int>> robust =
        RobustInliers(cloud, inliers[r], fit, c, c.robust_seed + static_cast<std::uint32_t>(r));
    if (robust) {
      if (static_cast<int>(robust->size()) >= config_.min_inliers) planes.push_back(FitDetectedPlane(cloud, std::move(*robust)));
      continue;
    }
    planes.push_back(MakeDetectedPlane(fit, std::move(inliers[r]), bounds[r]));
  }
  for (std::vector<int>& pixels : leftover) {
    planes.push_back(FitDetectedPlane(cloud, std::move(pixels)));
    planes.back().strip = true;
  }
  return FinishSegmentation(cloud, std::move(planes), valid_points, config_);
}

}  // namespace planemap
