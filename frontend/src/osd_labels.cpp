#include "planemap/frontend/osd_labels.h"

#include <algorithm>
#include <cmath>
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
#include "planemap/core/pose.h"
#include "planemap/core/statistics.h"

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

int OsdFacesShown(const std::vector<LabelledFace>& faces, const Eigen::Vector3d& up) {
  const double horizontal = std::cos(15.0 * M_PI / 180.0), vertical = std::sin(15.0 * M_PI / 180.0);
  const double apart = std::cos(60.0 * M_PI / 180.0);
  bool top = false, two_sides = false, two_faces = false;
  for (size_t a = 0; a < faces.size(); ++a) {
    const Eigen::Vector3d& na = faces[a].plane.normal;
    top = top || std::abs(na.dot(up)) > horizontal;
    for (size_t b = a + 1; b < faces.size(); ++b) {
      const Eigen::Vector3d& nb = faces[b].plane.normal;
      if (std::abs(na.dot(nb)) > apart) continue;
      two_faces = true;
      two_sides = two_sides || (std::abs(na.dot(up)) < vertical && std::abs(nb.dot(up)) < vertical);
    }
  }
  return top && two_sides ? 3 : (two_faces ? 2 : 1);
}

double OsdLabelledExtent(const Cloud& cloud, const std::vector<int>& points, const Eigen::Vector3d& axis,
                         const Plane& table) {
  std::vector<double> along, height;
  for (int i : points) {
    const Eigen::Vector3d x = cloud[i].getVector3fMap().cast<double>();
    along.push_back(axis.dot(x));
    height.push_back(table.SignedDistance(x));
  }
  if (points.empty()) return 0.0;
  if (std::abs(axis.dot(table.normal)) > std::cos(10.0 * M_PI / 180.0) && Percentile(height, 0.01) < 0.02) {
    return Percentile(height, 0.99);
  }
  return Percentile(along, 0.99) - Percentile(along, 0.01);
}

OsdBoxScore ScoreOsdBoxes(const Cloud& cloud, const std::vector<std::uint32_t>& labels, const FrameModel& model) {
  constexpr double kCentreMargin = 0.03, kCuboidMargin = 0.02;  // [m]
  OsdBoxScore score;
  const std::vector<LabelledFace> table = LabelledTable(cloud, labels);
  if (table.empty()) return score;
  std::map<int, std::vector<int>> points;
  for (size_t i = 0; i < labels.size(); ++i) {
    if (OsdObjectOf(labels[i]) > 0 && IsValidPoint(cloud[i])) points[OsdObjectOf(labels[i])].push_back(static_cast<int>(i));
  }
  std::map<int, Box3> bounds;
  for (const auto& [box, indices] : points) {
    for (int i : indices) bounds[box].Extend(cloud[i].getVector3fMap().cast<double>());
  }
  const auto centre_in = [&](const FrameObject& o, int box) {
    const Box3& b = bounds.at(box);
    return ((o.center.array() >= b.low.array() - kCentreMargin) && (o.center.array() <= b.high.array() + kCentreMargin)).all();
  };
  const auto held = [&](const FrameObject& o, const std::vector<int>& indices) {
    const Eigen::Array3d half = 0.5 * o.dimensions.array() + kCuboidMargin;
    int inside = 0;
    for (int i : indices) {
      const Eigen::Vector3d local = o.axes.transpose() * (cloud[i].getVector3fMap().cast<double>() - o.center);
      inside += (local.array().abs() <= half).all();
    }
    return indices.empty() ? 0.0 : static_cast<double>(inside) / indices.size();
  };
  for (const auto& [box, faces] : LabelledFaces(cloud, labels)) {
    OsdBoxResult result;
    result.box = box;
    result.faces_shown = OsdFacesShown(faces, table[0].plane.normal);
    const std::vector<int>& indices = points.at(box);
    for (size_t k = 0; k < model.objects.size(); ++k) {
      const FrameObject& o = model.objects[k];
      if (o.label != "box" || !centre_in(o, box)) continue;
      const double share = held(o, indices);
      if (share >= 0.5 && share > result.held) {
        result.held = share;
        result.object = static_cast<int>(k);
      }
    }
    if (result.object >= 0) {
      const FrameObject& o = model.objects[result.object];
      for (int k = 0; k < 3; ++k) {
        if (!o.dimension_complete[k]) continue;
        result.dimension_error.push_back(std::abs(o.dimensions[k] - OsdLabelledExtent(cloud, indices, o.axes.col(k), table[0].plane)));
      }
    }
    score.boxes.push_back(std::move(result));
  }
  for (const FrameObject& o : model.objects) {
    if (o.label != "box") continue;
    ++score.box_objects;
    bool near_a_box = false;
    for (const auto& [box, b] : bounds) near_a_box = near_a_box || centre_in(o, box);
    score.false_boxes += !near_a_box;
  }
  return score;
}

}  // namespace planemap
