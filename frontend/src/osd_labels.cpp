#include "planemap/frontend/osd_labels.h"

#include <algorithm>
#include <iterator>
#include <memory>
#include <numeric>

#include <opencv2/imgproc.hpp>
#include <pcl/ModelCoefficients.h>
#include <pcl/PointIndices.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include "planemap/core/detected_plane.h"

namespace planemap {
namespace {

constexpr int kMinFacePoints = 400;      // the segmenters' smallest plane [points]
constexpr double kFaceDistance = 0.005;  // a point within this of a face's plane is on it [m]
constexpr int kRansacIterations = 1000;
constexpr int kMaxFacesPerObject = 4;  // a box shows at most three faces; a fourth catches a stray one

// The largest 4-connected piece in the image of a RANSAC plane's inliers (given as positions in
// indices), refitted by least squares: a face is one connected patch, and labels sometimes hold a
// stray patch of points elsewhere that lies near the plane by chance and would tilt it.
LabelledFace LargestPiece(const Cloud& cloud, const std::vector<int>& indices, const pcl::Indices& inliers,
                          const Plane& ransac) {
  cv::Mat1b mask = cv::Mat1b::zeros(cloud.height, cloud.width);
  for (int i : inliers) mask(indices[i] / cloud.width, indices[i] % cloud.width) = 1;
  cv::Mat1i pieces, stats;
  cv::Mat centroids;
  const int count = cv::connectedComponentsWithStats(mask, pieces, stats, centroids, 4);
  int largest = 1;
  for (int k = 2; k < count; ++k) {
    if (stats(k, cv::CC_STAT_AREA) > stats(largest, cv::CC_STAT_AREA)) largest = k;
  }
  LabelledFace face{ransac, {}};
  PointMoments moments;
  for (int v = 0; v < pieces.rows; ++v) {
    for (int u = 0; u < pieces.cols; ++u) {
      if (pieces(v, u) != largest) continue;
      face.points.push_back(v * pieces.cols + u);
      moments.Add(cloud[face.points.back()].getVector3fMap().cast<double>());
    }
  }
  const PlaneFit fit = FitPlane(moments);
  if (fit.ok) face.plane = fit.plane;
  return face;
}

// The valid points whose label passes `keep`, ascending.
template <typename Keep>
std::vector<int> ValidPointsWhere(const Cloud& cloud, const std::vector<std::uint32_t>& labels, Keep keep) {
  std::vector<int> points;
  for (size_t i = 0; i < labels.size(); ++i) {
    if (keep(labels[i]) && IsValidPoint(cloud[i])) points.push_back(static_cast<int>(i));
  }
  return points;
}

}  // namespace

std::vector<LabelledFace> SacPlanes(const Cloud& cloud, const std::vector<int>& indices, int max_planes) {
  auto points = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (int i : indices) points->push_back(pcl::PointXYZ(cloud[i].x, cloud[i].y, cloud[i].z));
  pcl::SACSegmentation<pcl::PointXYZ> sac;
  sac.setOptimizeCoefficients(true);
  sac.setModelType(pcl::SACMODEL_PLANE);
  sac.setMethodType(pcl::SAC_RANSAC);
  sac.setDistanceThreshold(kFaceDistance);
  sac.setMaxIterations(kRansacIterations);
  sac.setInputCloud(points);
  auto remaining = std::make_shared<pcl::Indices>(points->size());
  std::iota(remaining->begin(), remaining->end(), 0);
  std::vector<LabelledFace> faces;
  while (static_cast<int>(faces.size()) < max_planes && remaining->size() >= kMinFacePoints) {
    pcl::PointIndices inliers;
    pcl::ModelCoefficients c;
    sac.setIndices(remaining);
    sac.segment(inliers, c);
    if (inliers.indices.size() < kMinFacePoints) break;
    Eigen::Vector3d n(c.values[0], c.values[1], c.values[2]);
    double offset = c.values[3] / n.norm();
    n.normalize();
    if (offset < 0) {  // toward the camera at the origin
      n = -n;
      offset = -offset;
    }
    std::sort(inliers.indices.begin(), inliers.indices.end());
    faces.push_back(LargestPiece(cloud, indices, inliers.indices, Plane{n, offset}));
    auto next = std::make_shared<pcl::Indices>();
    std::set_difference(remaining->begin(), remaining->end(), inliers.indices.begin(), inliers.indices.end(),
                        std::back_inserter(*next));
    remaining = next;
  }
  return faces;
}

std::map<int, std::vector<LabelledFace>> LabelledFaces(const Cloud& cloud,
                                                       const std::vector<std::uint32_t>& labels) {
  std::map<int, std::vector<int>> points;
  for (size_t i = 0; i < labels.size(); ++i) {
    if (OsdObjectOf(labels[i]) > 0 && IsValidPoint(cloud[i]))
      points[OsdObjectOf(labels[i])].push_back(static_cast<int>(i));
  }
  std::map<int, std::vector<LabelledFace>> faces;
  for (const auto& [object, indices] : points) faces[object] = SacPlanes(cloud, indices, kMaxFacesPerObject);
  return faces;
}

std::vector<LabelledFace> LabelledTable(const Cloud& cloud, const std::vector<std::uint32_t>& labels) {
  return SacPlanes(cloud, ValidPointsWhere(cloud, labels, IsOsdTable), 1);
}

LabelledSurfaces OsdSurfaces(const Cloud& cloud, const std::vector<std::uint32_t>& labels) {
  LabelledSurfaces surfaces;
  surfaces.labels = LabelImage(static_cast<int>(cloud.width), static_cast<int>(cloud.height));
  std::uint16_t next = 1;
  auto add = [&](const LabelledFace& face) {
    for (int i : face.points) surfaces.labels.pixels()[i] = next;
    surfaces.planes_camera[next++] = face.plane;
  };
  for (const LabelledFace& table : LabelledTable(cloud, labels)) add(table);
  if (next == 1) ++next;  // no table: the faces are 2, 3, ... all the same
  for (const auto& [object, faces] : LabelledFaces(cloud, labels)) {
    for (const LabelledFace& face : faces) add(face);
  }
  return surfaces;
}

}  // namespace planemap
