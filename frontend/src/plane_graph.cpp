#include "planemap/frontend/plane_graph.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

#include <Eigen/Dense>

#include "planemap/frontend/plane_segmenter.h"

namespace planemap {
namespace {

double DistanceToSegment(const Eigen::Vector3d& p, const PlaneEdge& e) {
  const Eigen::Vector3d d = e.end - e.start;
  const double t = std::clamp(d.dot(p - e.start) / std::max(d.squaredNorm(), 1e-12), 0.0, 1.0);
  return (e.start + t * d - p).norm();
}

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

Eigen::Vector3d UpPrior(const PlaneGraphConfig& config) {
  if (config.up_in_camera.size() != 3) return Eigen::Vector3d(0.0, -1.0, 0.0);
  return Eigen::Vector3d(config.up_in_camera[0], config.up_in_camera[1], config.up_in_camera[2]).normalized();
}

void FindStructure(const Cloud& cloud, const PlaneGraphConfig& config, FrameModel* model) {
  const std::vector<DetectedPlane>& planes = model->planes;
  const size_t n = planes.size();
  const Eigen::Vector3d up = UpPrior(config);
  const double floor_cos = std::cos(config.floor_max_angle_deg * M_PI / 180.0);
  model->floor = -1;
  for (size_t i = 0; i < n; ++i) {
    // Normals point toward the camera, so the floor's points up and its offset is the height.
    const Plane& p = planes[i].plane;
    if (p.normal.dot(up) < floor_cos || p.offset < config.floor_min_distance ||
        static_cast<int>(planes[i].inliers.size()) < config.floor_min_inliers) {
      continue;
    }
    if (model->floor < 0 || p.offset > planes[model->floor].plane.offset) model->floor = static_cast<int>(i);
  }
  model->structure.assign(n, false);
  for (size_t i = 0; i < n; ++i) {
    // The extent of a plane's inliers: the diagonal of their bounding box.
    model->structure[i] = static_cast<int>(i) == model->floor ||
                          InlierBounds(cloud, planes[i]).Diagonal() > config.structure_min_extent;
  }
}

void BuildPlaneGraph(const Cloud& cloud, const PlaneGraphConfig& config, FrameModel* model) {
  FindStructure(cloud, config, model);
  AggregateObjects(config, model);
}

void AggregateObjects(const PlaneGraphConfig& config, FrameModel* model) {
  const std::vector<DetectedPlane>& planes = model->planes;
  const size_t n = planes.size();

  // 1. Trihedral angles: 3-cycles of the graph whose three planes meet in a corner near all
  //    three edges.
  std::vector<std::vector<int>> adjacent(n);
  for (const PlaneEdge& e : model->edges) {
    adjacent[e.plane_a].push_back(e.plane_b);
    adjacent[e.plane_b].push_back(e.plane_a);
  }
  model->angles.clear();
  for (int a = 0; a < static_cast<int>(n); ++a) {
    for (int b : adjacent[a]) {
      if (b <= a) continue;
      for (int c : adjacent[b]) {
        if (c <= b || std::find(adjacent[a].begin(), adjacent[a].end(), c) == adjacent[a].end()) continue;
        Eigen::Matrix3d N;
        N << planes[a].plane.normal.transpose(), planes[b].plane.normal.transpose(), planes[c].plane.normal.transpose();
        if (std::abs(N.determinant()) < config.corner_min_determinant) continue;
        TrihedralAngle angle;
        angle.planes = {a, b, c};
        angle.edges = {model->EdgeBetween(a, b), model->EdgeBetween(a, c), model->EdgeBetween(b, c)};
        angle.corner = N.partialPivLu().solve(
            -Eigen::Vector3d(planes[a].plane.offset, planes[b].plane.offset, planes[c].plane.offset));
        // A hidden edge (at most one) was inferred from the corners it starts or ends at, with
        // the other two edges' ends cut short of them by the occluder: the angle is one of them.
        const int hidden = static_cast<int>(std::count_if(angle.edges.begin(), angle.edges.end(),
                                                          [&](int e) { return model->edges[e].hidden; }));
        bool near = hidden <= 1;
        for (int e : angle.edges) {
          const PlaneEdge& edge = model->edges[e];
          if (edge.hidden) {
            const double end = edge.end_cut ? 1e9 : (edge.end - angle.corner).norm();
            near = near && std::min((edge.start - angle.corner).norm(), end) < config.corner_snap_distance;
          } else if (hidden == 0) {
            near = near && DistanceToSegment(angle.corner, edge) < config.corner_max_distance;
          }
        }
        if (near) model->angles.push_back(angle);
      }
    }
  }
  // An edge that meets a corner ends there: the third face's points next to the corner lie
  // within d_thresh of both planes too, and their depth noise along the edge would lengthen it
  // (the farthest of many noisy points). The end nearer the corner moves to the corner's
  // projection on the edge's line, and is not cut, when that end is within corner_snap_distance
  // of it (a corner farther inside is where another object meets this edge, not its end).
  for (const TrihedralAngle& angle : model->angles) {
    for (int e : angle.edges) {
      PlaneEdge& edge = model->edges[e];
      const double s = (angle.corner - edge.start).dot(edge.direction);
      if (std::min(std::abs(s), std::abs(s - edge.length)) > config.corner_snap_distance) continue;
      const Eigen::Vector3d at = edge.start + s * edge.direction;
      if (s > 0.5 * edge.length) {
        edge.end = at;
        edge.end_cut = false;
      } else {
        edge.start = at;
        edge.start_cut = false;
      }
      edge.length = std::max(0.0, (edge.end - edge.start).dot(edge.direction));
    }
  }

  // 2. Objects: angles that share a graph edge (two planes) belong together, angle by angle.
  //    Structure planes are not faces of an object, and an edge between two structure planes
  //    (a wall on the floor) joins nothing: two lockers both standing on the floor stay apart.
  //    A concave edge between an upward-facing top and a vertical face that are not structure is
  //    one object resting on another (a box standing on a box): corners with such an edge belong
  //    to no object. (Other concave edges are an object's own: an open locker's inner corners.)
  const size_t m = model->angles.size();
  const Eigen::Vector3d up = model->floor >= 0 ? planes[model->floor].plane.normal : UpPrior(config);
  const double cos_tilt = std::cos(config.resting_max_tilt_deg * M_PI / 180.0);
  const double sin_tilt = std::sin(config.resting_max_tilt_deg * M_PI / 180.0);
  auto resting = [&](const PlaneEdge& edge) {
    if (edge.convex || model->structure[edge.plane_a] || model->structure[edge.plane_b]) return false;
    const double ca = planes[edge.plane_a].plane.normal.dot(up), cb = planes[edge.plane_b].plane.normal.dot(up);
    return (ca > cos_tilt && std::abs(cb) < sin_tilt) || (cb > cos_tilt && std::abs(ca) < sin_tilt);
  };
  std::vector<bool> object_angle(m, true);
  for (size_t i = 0; i < m; ++i) {
    for (int e : model->angles[i].edges) object_angle[i] = object_angle[i] && !resting(model->edges[e]);
  }
  //    An inner corner (all three edges concave: the inside of an open locker, Fig. 2, or the
  //    nook where two objects meet on the floor) joins an outer corner only through an edge
  //    between two faces, not through one with the floor.
  std::vector<bool> inner(m);
  for (size_t i = 0; i < m; ++i) {
    inner[i] = std::none_of(model->angles[i].edges.begin(), model->angles[i].edges.end(),
                            [&](int e) { return model->edges[e].convex; });
  }
  std::vector<int> parent(m);
  std::iota(parent.begin(), parent.end(), 0);
  for (size_t i = 0; i < m; ++i) {
    if (!object_angle[i]) continue;
    for (size_t j = i + 1; j < m; ++j) {
      if (!object_angle[j]) continue;
      for (int e : model->angles[i].edges) {
        const PlaneEdge& edge = model->edges[e];
        const bool with_structure = model->structure[edge.plane_a] || model->structure[edge.plane_b];
        if (with_structure && inner[i] != inner[j]) continue;
        if (model->structure[edge.plane_a] && model->structure[edge.plane_b]) continue;
        const auto& other = model->angles[j].edges;
        if (std::find(other.begin(), other.end(), e) != other.end()) parent[Find(parent, i)] = Find(parent, j);
      }
    }
  }
  model->objects.clear();
  std::vector<int> object_of_root(m, -1);
  for (size_t i = 0; i < m; ++i) {
    if (!object_angle[i]) continue;
    const int root = Find(parent, static_cast<int>(i));
    if (object_of_root[root] < 0) {
      object_of_root[root] = static_cast<int>(model->objects.size());
      model->objects.emplace_back();
    }
    model->objects[object_of_root[root]].angles.push_back(static_cast<int>(i));
  }
  for (FrameObject& object : model->objects) {
    std::set<int> faces;
    for (int a : object.angles) {
      for (int p : model->angles[a].planes) {
        if (!model->structure[p]) faces.insert(p);
      }
    }
    object.planes.assign(faces.begin(), faces.end());
  }
  // A lone inner corner with a face of another object is the nook between two objects.
  auto nook = [&](const FrameObject& object) {
    if (object.angles.size() != 1 || !inner[object.angles[0]]) return false;
    for (const FrameObject& other : model->objects) {
      if (&other == &object) continue;
      for (int p : object.planes) {
        if (std::count(other.planes.begin(), other.planes.end(), p) > 0) return true;
      }
    }
    return false;
  };
  std::vector<FrameObject> kept;
  for (FrameObject& object : model->objects) {
    if (object.planes.size() < 2 || nook(object)) continue;  // a room corner is no object
    kept.push_back(object);  // copied: nook() reads the others' planes
  }
  model->objects = std::move(kept);
}

}  // namespace planemap
