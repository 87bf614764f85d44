#include "planemap/frontend/plane_outline.h"

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace planemap {

std::vector<Eigen::Vector3d> PlaneOutline(const PlaneLandmark& landmark) {
  if (landmark.points.size() < 3) return {};
  // In-plane axes u, v with u x v = n, so the 2-D hull's counter-clockwise is the plane's.
  const Eigen::Vector3d& n = landmark.plane.normal;
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  // Coordinates relative to the first point: floats keep sub-millimetre steps near it.
  const Eigen::Vector3d first = landmark.points.front().cast<double>();
  std::vector<cv::Point2f> in_plane;
  in_plane.reserve(landmark.points.size());
  for (const Eigen::Vector3f& p : landmark.points) {
    const Eigen::Vector3d d = p.cast<double>() - first;
    in_plane.emplace_back(static_cast<float>(d.dot(u)), static_cast<float>(d.dot(v)));
  }
  std::vector<cv::Point2f> hull;
  cv::convexHull(in_plane, hull, /*clockwise=*/false);
  if (hull.size() < 3 || std::abs(cv::contourArea(hull)) < 1e-8) return {};
  // Back to the world, on the plane: its point nearest the first point, plus the 2-D offsets.
  const Eigen::Vector3d base = first - n * landmark.plane.SignedDistance(first);
  std::vector<Eigen::Vector3d> outline;
  outline.reserve(hull.size());
  for (const cv::Point2f& q : hull) outline.push_back(base + q.x * u + q.y * v);
  return outline;
}

}  // namespace planemap
