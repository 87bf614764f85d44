#include "planemap/core/plane_map.h"

#include <algorithm>
#include <cmath>

#include "planemap/core/plane.h"

namespace planemap {

int PlaneMap::EdgeBetween(int a, int b) const {
  if (a > b) std::swap(a, b);
  for (size_t i = 0; i < edges.size(); ++i) {
    if (edges[i].landmark_a == a && edges[i].landmark_b == b) return static_cast<int>(i);
  }
  return -1;
}

long long VoxelKey(const Eigen::Vector3f& p, double voxel) {
  const auto cell = [&](float x) { return static_cast<long long>(std::floor(x / voxel)) + (1LL << 20); };
  return (cell(p.x()) << 42) | (cell(p.y()) << 21) | cell(p.z());
}

int PlaneMap::Floor() const {
  int floor = -1;
  for (const PlaneLandmark& l : landmarks) {
    if (l.floor_votes > 0 && (floor < 0 || l.floor_votes > landmarks[floor].floor_votes)) floor = l.id;
  }
  return floor;
}

std::size_t PlaneMap::MemoryBytes() const {
  std::size_t bytes = sizeof(PlaneMap) + edges.size() * sizeof(MapEdge) + keyframes.size() * sizeof(Keyframe);
  for (const PlaneLandmark& l : landmarks) bytes += sizeof(PlaneLandmark) + l.points.size() * sizeof(Eigen::Vector3f);
  for (const MapObject& o : objects) bytes += sizeof(MapObject) + o.landmarks.size() * sizeof(int) + o.label.size();
  return bytes;
}

void TransformMap(const Pose3& T, PlaneMap* map) {
  const Eigen::Matrix3d R = T.linear();
  for (PlaneLandmark& l : map->landmarks) {
    l.plane = TransformPlane(T, l.plane);
    l.moments = TransformMoments(T, l.moments);
    for (Eigen::Vector3f& p : l.points) p = (T * p.cast<double>()).cast<float>();
    if (l.low.x() <= l.high.x()) {  // an extent (it holds the points)
      const Box3 box = TransformBox(T, l.low, l.high);
      l.low = box.low;
      l.high = box.high;
    }
  }
  for (MapEdge& e : map->edges) {
    e.start = T * e.start;
    e.end = T * e.end;
  }
  for (MapObject& o : map->objects) {
    o.axes = R * o.axes;
    o.center = T * o.center;
    o.grasp_axis = R * o.grasp_axis;
    o.center_sum = R * o.center_sum + o.center_count * T.translation();
    o.partial_center_sum = R * o.partial_center_sum + o.partial_center_count * T.translation();
    o.uncertainty.center_covariance = R * o.uncertainty.center_covariance * R.transpose();
  }
  for (Keyframe& k : map->keyframes) k.T_world_camera = T * k.T_world_camera;
}

double CuboidOverlap(const Eigen::Vector3d& center_a, const Eigen::Matrix3d& axes_a, const Eigen::Vector3d& dimensions_a,
                     const Eigen::Vector3d& center_b, const Eigen::Matrix3d& axes_b, const Eigen::Vector3d& dimensions_b,
                     double min_dimension) {
  const Eigen::Vector3d half_a = 0.5 * dimensions_a.cwiseMax(min_dimension);
  const Eigen::Vector3d half_b_own = 0.5 * dimensions_b.cwiseMax(min_dimension);
  // b's extent along a's axes: |R| half_b, R = axes_a^T axes_b (its box in a's frame).
  const Eigen::Matrix3d R = axes_a.transpose() * axes_b;
  const Eigen::Vector3d half_b = R.cwiseAbs() * half_b_own;
  const Eigen::Vector3d offset = axes_a.transpose() * (center_b - center_a);
  double intersection = 1.0;
  for (int k = 0; k < 3; ++k) {
    const double low = std::max(-half_a[k], offset[k] - half_b[k]), high = std::min(half_a[k], offset[k] + half_b[k]);
    intersection *= std::max(0.0, high - low);
  }
  const double smaller = std::min(8.0 * half_a.prod(), 8.0 * half_b_own.prod());
  return std::clamp(intersection / smaller, 0.0, 1.0);
}

}  // namespace planemap
