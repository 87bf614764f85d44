#include "planemap/frontend/plane_segmenter.h"

#include <algorithm>
#include <cmath>
#include <optional>
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

DetectedPlane FitDetectedPlane(const Cloud& cloud, std::vector<int> inliers) {
  PointMoments moments;
  for (int i : inliers) {
    const auto& p = cloud[i];
    moments.Add(Eigen::Vector3d(p.x, p.y, p.z), DepthNoiseWeight(p.z));
  }
  return MakeDetectedPlane(FitPlane(moments), std::move(inliers));
}

DetectedPlane MakeDetectedPlane(const PlaneFit& fit, std::vector<int> inliers) {
  DetectedPlane plane;
  plane.plane = fit.plane;
  plane.centroid = fit.centroid;
  plane.covariance = fit.covariance;
  plane.rms = fit.rms;
  plane.inliers = std::move(inliers);
  return plane;
}

namespace {

struct PixelBox {
  int u0 = 1 << 30, v0 = 1 << 30, u1 = -1, v1 = -1;
  int Gap(const PixelBox& o) const {
    const int du = std::max({0, o.u0 - u1, u0 - o.u1}), dv = std::max({0, o.v0 - v1, v0 - o.v1});
    return std::max(du, dv);
  }
};

// Merges pairs of planes with one equation whose pixels lie close, until none is left.
void MergeCoplanar(const Cloud& cloud, const SegmenterConfig& config, std::vector<DetectedPlane>* planes) {
  const double min_cos = std::cos(config.coplanar_max_angle_deg * M_PI / 180.0);
  const int w = static_cast<int>(cloud.width);
  // Pixel boxes are computed only for pairs whose equations agree (few), and cached.
  std::vector<std::optional<PixelBox>> boxes(planes->size());
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
  bool merged = true;
  while (merged) {
    merged = false;
    for (size_t a = 0; a < planes->size() && !merged; ++a) {
      for (size_t b = a + 1; b < planes->size() && !merged; ++b) {
        const DetectedPlane& pa = (*planes)[a];
        const DetectedPlane& pb = (*planes)[b];
        if (pa.plane.normal.dot(pb.plane.normal) < min_cos ||
            std::abs(pa.plane.SignedDistance(pb.centroid)) > config.coplanar_max_distance ||
            std::abs(pb.plane.SignedDistance(pa.centroid)) > config.coplanar_max_distance ||
            box_of(a).Gap(box_of(b)) > config.coplanar_max_gap) {
          continue;
        }
        std::vector<int> inliers = pa.inliers;
        inliers.insert(inliers.end(), pb.inliers.begin(), pb.inliers.end());
        std::sort(inliers.begin(), inliers.end());
        (*planes)[a] = FitDetectedPlane(cloud, std::move(inliers));
        planes->erase(planes->begin() + b);
        boxes.erase(boxes.begin() + b);
        boxes[a].reset();
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
