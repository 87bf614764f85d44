#include "planemap/frontend/plane_segmenter.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <set>
#include <stdexcept>

#include "planemap/frontend/msac_segmenter.h"
#include "planemap/frontend/organized_segmenter.h"

namespace planemap {

std::unique_ptr<PlaneSegmenter> MakePlaneSegmenter(const SegmenterConfig& config) {
  ValidateConfig(config, "segmentation.");
  if (config.method == "organized") return std::make_unique<OrganizedSegmenter>(config);
  if (config.method == "msac") return std::make_unique<MsacSegmenter>(config);
  throw std::invalid_argument("segmentation.method: unknown method '" + config.method + "' (known: organized, msac)");
}

namespace {

// PointMoments::Add's sums over the inliers, the six distinct ones of the symmetric outer product
// only, in scalars the compiler keeps in registers; with kBounds, their box into *bounds too.
template <bool kBounds>
PointMoments SumInliers(const Cloud& cloud, const std::vector<int>& inliers, Box3* bounds) {
  double w = 0.0, sx = 0.0, sy = 0.0, sz = 0.0, sxx = 0.0, sxy = 0.0, sxz = 0.0, syy = 0.0, syz = 0.0, szz = 0.0;
  float low[3] = {1e30f, 1e30f, 1e30f}, high[3] = {-1e30f, -1e30f, -1e30f};
  const pcl::PointXYZRGB* const points = cloud.points.data();
  for (const int i : inliers) {
    const pcl::PointXYZRGB& p = points[i];
    const double x = p.x, y = p.y, z = p.z;
    const double weight = DepthNoiseWeight(z);
    const double wx = weight * x, wy = weight * y, wz = weight * z;
    w += weight;
    sx += wx, sy += wy, sz += wz;
    sxx += wx * x, sxy += wx * y, sxz += wx * z;
    syy += wy * y, syz += wy * z, szz += wz * z;
    if constexpr (kBounds) {
      low[0] = std::min(low[0], p.x), low[1] = std::min(low[1], p.y), low[2] = std::min(low[2], p.z);
      high[0] = std::max(high[0], p.x), high[1] = std::max(high[1], p.y), high[2] = std::max(high[2], p.z);
    }
  }
  PointMoments moments;
  moments.n = static_cast<double>(inliers.size());
  moments.w = w;
  moments.sum = Eigen::Vector3d(sx, sy, sz);
  moments.sum_outer << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
  if (kBounds && !inliers.empty()) {
    bounds->Extend(Eigen::Vector3d(low[0], low[1], low[2]));
    bounds->Extend(Eigen::Vector3d(high[0], high[1], high[2]));
  }
  return moments;
}

}  // namespace

PointMoments InlierMoments(const Cloud& cloud, const std::vector<int>& inliers, Box3* bounds) {
  return bounds != nullptr ? SumInliers<true>(cloud, inliers, bounds) : SumInliers<false>(cloud, inliers, nullptr);
}

DetectedPlane FitDetectedPlane(const Cloud& cloud, std::vector<int> inliers) {
  Box3 box;
  const PointMoments moments = InlierMoments(cloud, inliers, &box);
  return MakeDetectedPlane(FitPlane(moments), std::move(inliers), box);
}

DetectedPlane MakeDetectedPlane(const PlaneFit& fit, std::vector<int> inliers, const Box3& bounds) {
  DetectedPlane plane;
  plane.plane = fit.plane;
  plane.centroid = fit.centroid;
  plane.covariance = fit.covariance;
  plane.rms = fit.rms;
  plane.inliers = std::move(inliers);
  plane.bounds = bounds;
  return plane;
}

Box3 InlierBounds(const Cloud& cloud, const DetectedPlane& plane) {
  if (!plane.bounds.Empty() || plane.inliers.empty()) return plane.bounds;
  Box3 box;
  for (int i : plane.inliers) box.Extend(cloud[i].getVector3fMap().cast<double>());
  return box;
}

namespace {

struct PixelBox {
  int u0 = 1 << 30, v0 = 1 << 30, u1 = -1, v1 = -1;
  Eigen::Vector2d Center() const { return Eigen::Vector2d(0.5 * (u0 + u1), 0.5 * (v0 + v1)); }
  PixelBox Union(const PixelBox& o) const {
    return {std::min(u0, o.u0), std::min(v0, o.v0), std::max(u1, o.u1), std::max(v1, o.v1)};
  }
  int Gap(const PixelBox& o) const {
    const int du = std::max({0, o.u0 - u1, u0 - o.u1}), dv = std::max({0, o.v0 - v1, v0 - o.v1});
    return std::max(du, dv);
  }
};

// What the camera sees between two coplanar pieces, along the image segment between pixels
// `from` and `to` (their pixel boxes' centres): of the pixels of neither (with depth), how many
// lie farther than the surface the pieces would span (the camera sees past it: two box tops of
// one height with the floor between them) and how many nearer (an occluder in front of one
// surface, which is what cut it in two).
struct Between {
  int pixels = 0, behind = 0, nearer = 0;
};

Between LookBetween(const Cloud& cloud, const DetectedPlane& a, const DetectedPlane& b, const Eigen::Vector2d& from,
                    const Eigen::Vector2d& to, const SegmenterConfig& config) {
  const int w = static_cast<int>(cloud.width), h = static_cast<int>(cloud.height);
  const Plane surface{(a.plane.normal + b.plane.normal).normalized(), 0.5 * (a.plane.offset + b.plane.offset)};
  const int steps = static_cast<int>(std::ceil((to - from).norm()));
  Between between;
  for (int k = 0; k <= steps; ++k) {
    const Eigen::Vector2d uv = from + (to - from) * (steps > 0 ? static_cast<double>(k) / steps : 0.0);
    const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
    if (u < 0 || v < 0 || u >= w || v >= h) continue;
    const int i = v * w + u;
    if (std::binary_search(a.inliers.begin(), a.inliers.end(), i) ||
        std::binary_search(b.inliers.begin(), b.inliers.end(), i) || !IsValidPoint(cloud[i])) {
      continue;
    }
    const Eigen::Vector3d p(cloud[i].x, cloud[i].y, cloud[i].z);
    const Eigen::Vector3d ray = p.normalized();
    if (std::abs(surface.normal.dot(ray)) < 1e-6) continue;
    ++between.pixels;
    // Where the pixel's ray meets the surface; the margin grows with the square of the depth, as
    // the depth noise does.
    const std::optional<double> range = surface.IntersectRay(Eigen::Vector3d::Zero(), ray);
    const double margin = config.coplanar_see_through_margin * std::max(1.0, p.z() * p.z());
    if (!range || *range <= 0.0) continue;
    if (p.norm() > *range + margin) ++between.behind;
    if (p.norm() < *range - margin) ++between.nearer;
  }
  return between;
}

// Merges pairs of planes with one equation whose pixels lie close, until none is left. Pairs are
// tried in index order and the first that merges restarts the search, so the outcome is that of
// trying every pair again after each merge; a pair once refused is not tried again while neither
// of its planes changes (what decides it depends on the two planes alone).
void MergeCoplanar(const Cloud& cloud, const SegmenterConfig& config, std::vector<DetectedPlane>* planes) {
  const double min_cos = std::cos(config.coplanar_max_angle_deg * M_PI / 180.0);
  const int w = static_cast<int>(cloud.width);
  // Pixel boxes and the moments of FitDetectedPlane are computed only for pairs whose equations
  // agree (few), and cached.
  std::vector<std::optional<PixelBox>> boxes(planes->size());
  std::vector<std::optional<PointMoments>> moments(planes->size());
  auto box_of = [&](size_t k) -> const PixelBox& {
    if (!boxes[k]) {
      PixelBox b;
      for (int i : (*planes)[k].inliers) {
        b.u0 = std::min(b.u0, i % w), b.u1 = std::max(b.u1, i % w);
        b.v0 = std::min(b.v0, i / w), b.v1 = std::max(b.v1, i / w);
      }
      boxes[k] = b;
    }
    return *boxes[k];
  };
  auto moments_of = [&](size_t k) -> const PointMoments& {
    if (!moments[k]) moments[k] = InlierMoments(cloud, (*planes)[k].inliers);
    return *moments[k];
  };
  // Each plane's identity: a merged plane gets a new one, so refusals of its parts do not stick.
  std::vector<int> uid(planes->size());
  std::iota(uid.begin(), uid.end(), 0);
  int next_uid = static_cast<int>(planes->size());
  std::set<std::pair<int, int>> refused;
  bool merged = true;
  while (merged) {
    merged = false;
    for (size_t a = 0; a < planes->size() && !merged; ++a) {
      for (size_t b = a + 1; b < planes->size() && !merged; ++b) {
        const DetectedPlane& pa = (*planes)[a];
        const DetectedPlane& pb = (*planes)[b];
        if (pa.strip != pb.strip || pa.plane.normal.dot(pb.plane.normal) < min_cos ||
            std::abs(pa.plane.SignedDistance(pb.centroid)) > config.coplanar_max_distance ||
            std::abs(pb.plane.SignedDistance(pa.centroid)) > config.coplanar_max_distance ||
            box_of(a).Gap(box_of(b)) > std::max(config.coplanar_max_gap, config.coplanar_max_occluded_gap) ||
            refused.count({uid[a], uid[b]}) > 0) {
          continue;
        }
        auto refuse = [&] { refused.insert({uid[a], uid[b]}); };
        const int gap = box_of(a).Gap(box_of(b));
        const Between between = LookBetween(cloud, pa, pb, box_of(a).Center(), box_of(b).Center(), config);
        if (between.pixels > 0 && between.behind > config.coplanar_max_see_through * between.pixels) {
          refuse();
          continue;
        }
        const bool occluded = between.pixels > 0 && between.nearer >= config.coplanar_min_occluded * between.pixels;
        const int max_gap = occluded ? std::max(config.coplanar_max_gap, config.coplanar_max_occluded_gap) : config.coplanar_max_gap;
        if (gap > max_gap) {
          refuse();
          continue;
        }
        // One surface: the plane through both fits them about as well as each piece's own plane
        // fits it, or as well as the depth resolution allows (pieces of a wall facing the camera
        // lie on the sensor's depth steps, each flatter than the noise). Two parallel faces a step
        // apart do not: a box's side and the side of the box stacked on it, 1.7 cm apart at
        // 0.6 m, fit one plane at 6.7 mm RMS against 2.1 and 2.2 mm each. The joint fit is that
        // of FitDetectedPlane on both inlier sets, from the sum of their moments (kept for the merged
        // plane: a wall in many pieces is merged piece by piece).
        PointMoments joint = moments_of(a);
        joint += moments_of(b);
        const PlaneFit both_fit = FitPlane(joint);
        const double na = static_cast<double>(pa.inliers.size()), nb = static_cast<double>(pb.inliers.size());
        const double pooled = std::sqrt((na * pa.rms * pa.rms + nb * pb.rms * pb.rms) / (na + nb));
        const double z = 0.5 * (pa.centroid.z() + pb.centroid.z());
        if (both_fit.rms > config.coplanar_max_rms_ratio * std::max(pooled, config.coplanar_rms_floor * z * z)) {
          refuse();
          continue;
        }
        // Both are sorted and disjoint: one linear merge (std::sort of two sorted runs fell back to
        // heapsort and took a tenth of the frontend).
        std::vector<int> inliers(pa.inliers.size() + pb.inliers.size());
        std::merge(pa.inliers.begin(), pa.inliers.end(), pb.inliers.begin(), pb.inliers.end(),
                   inliers.begin());
        const PixelBox box_a = box_of(a), box_b = box_of(b);
        Box3 bounds = InlierBounds(cloud, pa);
        bounds.Extend(InlierBounds(cloud, pb));
        DetectedPlane both = MakeDetectedPlane(both_fit, std::move(inliers), bounds);
        both.strip = pa.strip;  // strips merge with strips only (a strip is no landmark)
        (*planes)[a] = std::move(both);
        planes->erase(planes->begin() + b);
        boxes.erase(boxes.begin() + b);
        moments.erase(moments.begin() + b);
        uid.erase(uid.begin() + b);
        boxes[a] = box_a.Union(box_b);
        moments[a] = joint;
        uid[a] = next_uid++;
        merged = true;
      }
    }
  }
}

}  // namespace

SegmentationResult FinishSegmentation(const Cloud& cloud, std::vector<DetectedPlane> planes, int valid_points,
                                      const SegmenterConfig& config) {
  MergeCoplanar(cloud, config, &planes);
  // The angle between the plane and the ray to its centroid: cos = d / |centroid|.
  const double min_cos = std::cos(config.max_view_angle_deg * M_PI / 180.0);
  planes.erase(std::remove_if(planes.begin(), planes.end(),
                              [&](const DetectedPlane& p) { return p.plane.offset < min_cos * p.centroid.norm(); }),
               planes.end());
  std::stable_sort(planes.begin(), planes.end(),
                   [](const DetectedPlane& a, const DetectedPlane& b) { return a.inliers.size() > b.inliers.size(); });
  for (size_t i = 0; i < planes.size(); ++i) planes[i].id = static_cast<int>(i);
  SegmentationResult result;
  result.planes = std::move(planes);
  result.valid_points = valid_points;
  if (valid_points == 0) {
    result.reason = "no valid depth in the frame";
  } else if (result.planes.empty()) {
    result.reason = "no plane with enough inliers among " + std::to_string(valid_points) + " valid points";
  }
  return result;
}

}  // namespace planemap
