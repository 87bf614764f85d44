#include "planemap/frontend/plane_segmenter.h"

#include <algorithm>
#include <cmath>
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
  const PlaneFit fit = FitPlane(moments);
  DetectedPlane plane;
  plane.plane = fit.plane;
  plane.centroid = fit.centroid;
  plane.covariance = fit.covariance;
  plane.rms = fit.rms;
  plane.inliers = std::move(inliers);
  return plane;
}

SegmentationResult FinishSegmentation(std::vector<DetectedPlane> planes, int valid_points,
                                      const SegmenterConfig& config) {
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
