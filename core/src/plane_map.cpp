#include "planemap/core/plane_map.h"

#include <algorithm>

namespace planemap {

int PlaneMap::EdgeBetween(int a, int b) const {
  if (a > b) std::swap(a, b);
  for (size_t i = 0; i < edges.size(); ++i) {
    if (edges[i].landmark_a == a && edges[i].landmark_b == b) return static_cast<int>(i);
  }
  return -1;
}

std::size_t PlaneMap::MemoryBytes() const {
  std::size_t bytes = sizeof(PlaneMap) + edges.size() * sizeof(MapEdge) + keyframes.size() * sizeof(Keyframe);
  for (const PlaneLandmark& l : landmarks) bytes += sizeof(PlaneLandmark) + l.points.size() * sizeof(Eigen::Vector3f);
  for (const MapObject& o : objects) bytes += sizeof(MapObject) + o.landmarks.size() * sizeof(int) + o.label.size();
  return bytes;
}

}  // namespace planemap
