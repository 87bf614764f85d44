#include "planemap/frontend/msac_segmenter.h"

#include <algorithm>

#include <pcl/ModelCoefficients.h>
#include <pcl/PointIndices.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

namespace planemap {

std::vector<std::vector<int>> ConnectedParts(const std::vector<int>& pixels, int width, int height) {
  std::vector<int> label(static_cast<size_t>(width) * height, -2);  // -2: not in the set
  for (int p : pixels) label[p] = -1;                                // -1: not visited yet
  std::vector<std::vector<int>> parts;
  std::vector<int> stack;
  for (int start : pixels) {
    if (label[start] != -1) continue;
    const int id = static_cast<int>(parts.size());
    parts.emplace_back();
    label[start] = id;
    stack.assign(1, start);
    while (!stack.empty()) {
      const int p = stack.back();
      stack.pop_back();
      parts[id].push_back(p);
      const int u = p % width, v = p / width;
      for (int dv = -1; dv <= 1; ++dv) {
        for (int du = -1; du <= 1; ++du) {
          const int uu = u + du, vv = v + dv;
          if (uu < 0 || uu >= width || vv < 0 || vv >= height) continue;
          const int q = vv * width + uu;
          if (label[q] == -1) {
            label[q] = id;
            stack.push_back(q);
          }
        }
      }
    }
    std::sort(parts[id].begin(), parts[id].end());
  }
  return parts;
}

SegmentationResult MsacSegmenter::Segment(const Cloud& cloud) const {
  const MsacSegmenterConfig& c = config_.msac;
  // The valid points, and for each its pixel.
  auto points = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  std::vector<int> pixel_of;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (!IsValidPoint(cloud[i])) continue;
    points->push_back(pcl::PointXYZ(cloud[i].x, cloud[i].y, cloud[i].z));
    pixel_of.push_back(static_cast<int>(i));
  }
  const int valid_points = static_cast<int>(points->size());

  pcl::SACSegmentation<pcl::PointXYZ> sac;  // fixed seed: deterministic
  sac.setOptimizeCoefficients(false);       // the least-squares refit below does this
  sac.setModelType(pcl::SACMODEL_PLANE);
  sac.setMethodType(pcl::SAC_MSAC);
  sac.setDistanceThreshold(c.distance_threshold);
  sac.setMaxIterations(c.max_iterations);
  sac.setProbability(c.probability);
  sac.setInputCloud(points);

  auto remaining = std::make_shared<pcl::Indices>(points->size());
  for (size_t i = 0; i < remaining->size(); ++i) (*remaining)[i] = static_cast<int>(i);
  std::vector<DetectedPlane> planes;
  for (int k = 0; k < c.max_planes && static_cast<int>(remaining->size()) >= config_.min_inliers; ++k) {
    pcl::PointIndices inliers;
    pcl::ModelCoefficients coefficients;
    sac.setIndices(remaining);
    sac.segment(inliers, coefficients);
    if (static_cast<int>(inliers.indices.size()) < config_.min_inliers) break;
    // One plane equation may cover several surfaces (two tables at one height): keep each
    // connected part on the image grid as a plane of its own.
    std::vector<int> pixels;
    pixels.reserve(inliers.indices.size());
    for (int i : inliers.indices) pixels.push_back(pixel_of[i]);
    for (std::vector<int>& part : ConnectedParts(pixels, static_cast<int>(cloud.width), static_cast<int>(cloud.height))) {
      if (static_cast<int>(part.size()) >= config_.min_inliers) planes.push_back(FitDetectedPlane(cloud, std::move(part)));
    }
    std::vector<int> used = inliers.indices;
    std::sort(used.begin(), used.end());
    auto next = std::make_shared<pcl::Indices>();
    std::set_difference(remaining->begin(), remaining->end(), used.begin(), used.end(), std::back_inserter(*next));
    remaining = next;
  }
  return FinishSegmentation(cloud, std::move(planes), valid_points, config_);
}

}  // namespace planemap
