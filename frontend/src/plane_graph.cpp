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

// Whether plane `support` is seen beside a face's lowest points (`pixels`: the face's, in an
// organized cloud; those within two_face_support_gap of `low` over the support): from each, in each
// of 8 directions in the image, the first pixel with depth past the face's own within 8 pixels
// lies on the support (within two_face_support_gap) for a tenth of them or more. Not in an
// unorganized cloud (a map's points).
bool SupportBeside(const Cloud& cloud, const std::vector<int>& pixels, const Plane& support, double low,
                   const PlaneGraphConfig& config) {
  constexpr int kSearch = 8;  // [px]
  const double gap = config.two_face_support_gap;
  if (cloud.height <= 1) return false;  // not organized (a map's points): a seen edge is needed
  const int width = static_cast<int>(cloud.width), height = static_cast<int>(cloud.height);
  std::vector<char> mask(cloud.size(), 0);
  for (int i : pixels) mask[i] = 1;
  int on_support = 0, looks = 0;
  for (int i : pixels) {
    if (support.SignedDistance(cloud[i].getVector3fMap().cast<double>()) > low + gap) continue;
    const int u = i % width, v = i / width;
    for (int du = -1; du <= 1; ++du) {
      for (int dv = -1; dv <= 1; ++dv) {
        if (du == 0 && dv == 0) continue;
        for (int step = 1; step <= kSearch; ++step) {
          const int qu = u + step * du, qv = v + step * dv;
          if (qu < 0 || qv < 0 || qu >= width || qv >= height) break;
          const int q = qv * width + qu;
          if (mask[q] || !IsValidPoint(cloud[q])) continue;
          ++looks;
          on_support += std::abs(support.SignedDistance(cloud[q].getVector3fMap().cast<double>())) <= gap;
          break;
        }
      }
    }
  }
  return looks > 0 && on_support >= 0.1 * looks;
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
  FindFaces(cloud, config, model);
  AggregateObjects(cloud, config, model);
}

void FindFaces(const Cloud& cloud, const PlaneGraphConfig& config, FrameModel* model) {
  const std::vector<DetectedPlane>& planes = model->planes;
  const int n = static_cast<int>(planes.size());
  model->face_of.resize(n);
  std::iota(model->face_of.begin(), model->face_of.end(), 0);
  model->face_plane.clear();
  for (const DetectedPlane& p : planes) model->face_plane.push_back(p.plane);
  if (config.face_piece_max_angle_deg <= 0.0) return;
  const double cos_max = std::cos(config.face_piece_max_angle_deg * M_PI / 180.0);
  auto rms_to = [&](const Plane& plane, const std::vector<int>& inliers) {
    double sum = 0.0;
    for (int i : inliers) sum += std::pow(plane.SignedDistance(cloud[i].getVector3fMap().cast<double>()), 2);
    return inliers.empty() ? 0.0 : std::sqrt(sum / inliers.size());
  };
  auto joint = [&](const std::vector<int>& members) {
    std::vector<int> inliers;
    for (int p : members) inliers.insert(inliers.end(), planes[p].inliers.begin(), planes[p].inliers.end());
    std::sort(inliers.begin(), inliers.end());
    return FitDetectedPlane(cloud, std::move(inliers)).plane;
  };
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (const PlaneEdge& ea : model->edges) {
    for (const PlaneEdge& eb : model->edges) {
      if (&eb <= &ea || ea.hidden || eb.hidden || ea.convex != eb.convex) continue;
      // The plane both edges share, and the two pieces.
      int c = -1, a = -1, b = -1;
      for (int x : {ea.plane_a, ea.plane_b}) {
        if (x == eb.plane_a || x == eb.plane_b) c = x;
      }
      if (c < 0) continue;
      a = ea.plane_a == c ? ea.plane_b : ea.plane_a;
      b = eb.plane_a == c ? eb.plane_b : eb.plane_a;
      if (a == b || model->structure[a] || model->structure[b] || model->EdgeBetween(a, b) >= 0) continue;
      if (std::abs(planes[a].plane.normal.dot(planes[b].plane.normal)) < cos_max ||
          std::abs(ea.direction.dot(eb.direction)) < cos_max) {
        continue;
      }
      // Side by side along the line, not one across from the other (a rounded corner between a
      // face and the third plane meets the third plane beside the face's own edge): their
      // stretches along the line overlap by at most face_piece_max_overlap. Concave edges may be
      // two objects' standing on one plane: their pieces also leave at most face_piece_max_gap.
      const PlaneEdge& longer = ea.length >= eb.length ? ea : eb;
      auto stretch = [&](const PlaneEdge& e) {
        const double s0 = longer.direction.dot(e.start - longer.start), s1 = longer.direction.dot(e.end - longer.start);
        return std::make_pair(std::min(s0, s1), std::max(s0, s1));
      };
      const auto [lo_a, hi_a] = stretch(ea);
      const auto [lo_b, hi_b] = stretch(eb);
      const double overlap = std::min(hi_a, hi_b) - std::max(lo_a, lo_b);  // < 0: a gap
      if (overlap > config.face_piece_max_overlap || (!ea.convex && -overlap > config.face_piece_max_gap)) continue;
      const Plane both = joint({a, b});
      const double rms_a = rms_to(both, planes[a].inliers), rms_b = rms_to(both, planes[b].inliers);
      if (std::max(rms_a, rms_b) > config.face_piece_max_rms) continue;
      parent[Find(parent, std::max(a, b))] = Find(parent, std::min(a, b));
    }
  }
  // Pieces of the floor: room structure as parallel to the floor and as close to the plane fitted
  // to both as a face's pieces are (a strip of floor the segmenter found apart, beside a box's
  // base at a glancing angle) is the floor, so a box's sides meet the floor there.
  if (model->floor >= 0) {
    const int floor = model->floor;
    for (int p = 0; p < n; ++p) {
      if (p == floor || !model->structure[p] ||
          planes[p].plane.normal.dot(planes[floor].plane.normal) < cos_max) {
        continue;
      }
      const Plane both = joint({floor, p});
      if (std::max(rms_to(both, planes[floor].inliers), rms_to(both, planes[p].inliers)) > config.face_piece_max_rms) continue;
      parent[Find(parent, p)] = Find(parent, floor);
    }
  }
  std::vector<std::vector<int>> members(n);
  for (int p = 0; p < n; ++p) members[Find(parent, p)].push_back(p);
  for (int root = 0; root < n; ++root) {
    if (members[root].size() < 2) continue;
    const Plane face = joint(members[root]);
    for (int p : members[root]) {
      model->face_of[p] = members[root].front();
      model->face_plane[p] = face;
    }
  }
}

void AggregateObjects(const Cloud& cloud, const PlaneGraphConfig& config, FrameModel* model) {
  const std::vector<DetectedPlane>& planes = model->planes;
  const size_t n = planes.size();

  // 1. Trihedral angles: 3-cycles of the graph of faces (a plane, or the pieces of one face:
  //    FindFaces) whose three faces meet in a corner near all three edges. Between two faces in
  //    pieces there may be several edges; the angle takes the one nearest its corner.
  std::vector<std::vector<int>> adjacent(n);
  std::vector<std::vector<std::vector<int>>> edges_between(n);  // [face][k]: edges to adjacent[face][k]
  auto face = [&](int p) { return model->FaceOf(p); };
  for (size_t e = 0; e < model->edges.size(); ++e) {
    const int a = face(model->edges[e].plane_a), b = face(model->edges[e].plane_b);
    if (a == b) continue;
    for (const auto& [x, y] : {std::pair<int, int>{a, b}, std::pair<int, int>{b, a}}) {
      const size_t k = std::find(adjacent[x].begin(), adjacent[x].end(), y) - adjacent[x].begin();
      if (k == adjacent[x].size()) {
        adjacent[x].push_back(y);
        edges_between[x].emplace_back();
      }
      edges_between[x][k].push_back(static_cast<int>(e));
    }
  }
  auto edges_of = [&](int x, int y) -> const std::vector<int>& {
    return edges_between[x][std::find(adjacent[x].begin(), adjacent[x].end(), y) - adjacent[x].begin()];
  };
  model->angles.clear();
  for (int a = 0; a < static_cast<int>(n); ++a) {
    for (int b : adjacent[a]) {
      if (b <= a) continue;
      for (int c : adjacent[b]) {
        if (c <= b || std::find(adjacent[a].begin(), adjacent[a].end(), c) == adjacent[a].end()) continue;
        const Plane &pa = model->FacePlane(a), &pb = model->FacePlane(b), &pc = model->FacePlane(c);
        Eigen::Matrix3d N;
        N << pa.normal.transpose(), pb.normal.transpose(), pc.normal.transpose();
        if (std::abs(N.determinant()) < config.corner_min_determinant) continue;
        TrihedralAngle angle;
        angle.planes = {a, b, c};
        angle.corner = N.partialPivLu().solve(-Eigen::Vector3d(pa.offset, pb.offset, pc.offset));
        const std::array<std::pair<int, int>, 3> pairs{{{a, b}, {a, c}, {b, c}}};
        for (int k = 0; k < 3; ++k) {
          const std::vector<int>& candidates = edges_of(pairs[k].first, pairs[k].second);
          angle.edges[k] = *std::min_element(candidates.begin(), candidates.end(), [&](int x, int y) {
            return DistanceToSegment(angle.corner, model->edges[x]) < DistanceToSegment(angle.corner, model->edges[y]);
          });
        }
        // A hidden edge (at most one) was inferred from the corners it starts or ends at, with
        // the other two edges' ends cut short of them by the occluder: the angle is one of them.
        const int hidden = static_cast<int>(std::count_if(angle.edges.begin(), angle.edges.end(),
                                                          [&](int e) { return model->edges[e].hidden; }));
        // One seen edge may reach the corner only on its line, beyond an end of it that is cut
        // (the edge may go on past it): a ledge narrower than d_thresh beside the face it meets
        // has no band points there. The other two then end at the corner: each has a whole end
        // within corner_snap_distance of it.
        bool near = hidden <= 1;
        int extended = 0;
        auto ends_at_corner = [&](const PlaneEdge& edge) {
          return (!edge.start_cut && (edge.start - angle.corner).norm() < config.corner_snap_distance) ||
                 (!edge.end_cut && (edge.end - angle.corner).norm() < config.corner_snap_distance);
        };
        for (int e : angle.edges) {
          const PlaneEdge& edge = model->edges[e];
          if (edge.hidden) {
            const double end = edge.end_cut ? 1e9 : (edge.end - angle.corner).norm();
            near = near && std::min((edge.start - angle.corner).norm(), end) < config.corner_snap_distance;
          } else if (hidden == 0 && DistanceToSegment(angle.corner, edge) >= config.corner_max_distance) {
            const double s = (angle.corner - edge.start).dot(edge.direction);
            const bool beyond_cut = (s < 0.0 && edge.start_cut && -s < config.corner_past_cut_distance) ||
                                    (s > edge.length && edge.end_cut && s - edge.length < config.corner_past_cut_distance);
            const bool on_line = (angle.corner - edge.start - s * edge.direction).norm() < config.corner_snap_distance;
            near = near && beyond_cut && on_line && ++extended == 1;
          }
        }
        for (int e : angle.edges) {
          if (near && extended == 1 && DistanceToSegment(angle.corner, model->edges[e]) < config.corner_max_distance) {
            near = ends_at_corner(model->edges[e]);  // one of the two others
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
  // Every edge between two of the angle's faces (a face in pieces may meet another in several).
  for (const TrihedralAngle& angle : model->angles) {
    std::vector<int> between;
    for (const auto& [x, y] : {std::pair<int, int>{0, 1}, {0, 2}, {1, 2}}) {
      const std::vector<int>& e = edges_of(angle.planes[x], angle.planes[y]);
      between.insert(between.end(), e.begin(), e.end());
    }
    for (int e : between) {
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
    const double ca = model->FacePlane(edge.plane_a).normal.dot(up), cb = model->FacePlane(edge.plane_b).normal.dot(up);
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
        // The same two faces (pieces of a face may meet the other face in several edges).
        const auto& other = model->angles[j].planes;
        if (std::count(other.begin(), other.end(), face(edge.plane_a)) > 0 &&
            std::count(other.begin(), other.end(), face(edge.plane_b)) > 0) {
          parent[Find(parent, i)] = Find(parent, j);
        }
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
      for (int f : model->angles[a].planes) {
        for (int p = 0; p < static_cast<int>(n); ++p) {
          if (face(p) == f && !model->structure[p]) faces.insert(p);  // every piece of the face
        }
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

  // 3. Objects of two faces on a support (PlaneGraphConfig::two_face_*): a box showing its top
  //    and front, or two sides, its third face turned away or hidden. Such faces meet in a convex
  //    edge, as a solid's do; the support a vertical one stands on (a concave edge with a plane
  //    facing up) tells a box on a table from a table's top and its apron, which stands on
  //    nothing. Faces joined by such edges are one object (a front with its top and a side).
  if (config.two_face_min_angle_deg <= 0.0) return;
  const double cos_apart = std::cos(config.two_face_min_angle_deg * M_PI / 180.0);
  std::vector<bool> taken(n, false);
  for (const FrameObject& object : model->objects) {
    for (int p : object.planes) taken[face(p)] = true;
  }
  auto normal = [&](int f) -> const Eigen::Vector3d& { return model->FacePlane(f).normal; };
  auto vertical = [&](int f) { return std::abs(normal(f).dot(up)) < sin_tilt; };
  auto facing_up = [&](int f) { return normal(f).dot(up) > cos_tilt; };
  // The support under vertical face f: a plane facing up that it stands on (at most
  // two_face_below_share of its points more than two_face_below_distance beneath it) and that
  // it meets in a seen concave edge, or whose plane its lowest points (1st percentile) reach
  // within two_face_support_gap of, beside the plane's points (the edge is missed where the
  // support is seen at a glancing angle). Of several, one its lowest points reach (a box standing
  // on a lower box stands on the table too, as far as its points go), the one with most points (a
  // floor in pieces: a small piece is fitted less well); else the highest. -1 if none.
  std::vector<int> support_cache(n, -2);  // -2: not computed yet
  auto find_support = [&](int f) {
    if (!vertical(f)) return -1;
    std::vector<int> pixels;
    for (int p = 0; p < static_cast<int>(n); ++p) {
      if (face(p) == f) pixels.insert(pixels.end(), planes[p].inliers.begin(), planes[p].inliers.end());
    }
    if (pixels.empty()) return -1;
    int support = -1;
    bool touching = false;  // the support's plane within two_face_support_gap of the face's lowest points
    double lowest = 0.0;    // their height over it [m]
    size_t largest = 0;     // its inliers
    std::vector<double> heights(pixels.size());
    for (int s = 0; s < static_cast<int>(n); ++s) {
      if (face(s) != s || s == f || !facing_up(s)) continue;
      const Plane& plane = model->FacePlane(s);
      size_t below = 0;
      for (size_t k = 0; k < pixels.size(); ++k) {
        heights[k] = plane.SignedDistance(cloud[pixels[k]].getVector3fMap().cast<double>());
        below += heights[k] < -config.two_face_below_distance;
      }
      if (below > config.two_face_below_share * pixels.size()) continue;
      const size_t k = static_cast<size_t>(0.01 * heights.size());
      std::nth_element(heights.begin(), heights.begin() + k, heights.end());
      const double low = heights[k];
      bool meets = false;
      for (const PlaneEdge& e : model->edges) {
        meets = meets || (!e.hidden && !e.convex && ((face(e.plane_a) == f && face(e.plane_b) == s) ||
                                                      (face(e.plane_a) == s && face(e.plane_b) == f)));
      }
      if (!meets && low <= config.two_face_support_gap) meets = SupportBeside(cloud, pixels, plane, low, config);
      // The plane the face's bottom touches; of several (a floor in pieces), the one with most
      // points, the best fitted; else the highest.
      size_t size = 0;
      for (int p = 0; p < static_cast<int>(n); ++p) size += face(p) == s ? planes[p].inliers.size() : 0;
      const bool touches = low <= config.two_face_support_gap;
      const bool better = support < 0 || (touches && !touching) ||
                          (touches == touching && (touches ? size > largest : low < lowest));
      if (meets && better) {
        support = s;
        touching = touches;
        lowest = low;
        largest = size;
      }
    }
    return support;
  };
  auto support_of = [&](int f) {
    if (support_cache[f] == -2) support_cache[f] = find_support(f);
    return support_cache[f];
  };
  std::vector<int> group(n);
  std::iota(group.begin(), group.end(), 0);
  std::vector<int> support_of_group(n, -1);
  for (const PlaneEdge& e : model->edges) {
    const int a = face(e.plane_a), b = face(e.plane_b);
    if (e.hidden || !e.convex || a == b || model->structure[a] || model->structure[b] || taken[a] || taken[b] ||
        std::abs(normal(a).dot(normal(b))) > cos_apart) {
      continue;
    }
    int support = -1;
    if (vertical(a) && vertical(b)) {
      const int sa = support_of(a), sb = support_of(b);
      support = sa >= 0 ? sa : sb;
    } else if (vertical(a) != vertical(b)) {
      const int side = vertical(a) ? a : b, top = vertical(a) ? b : a;
      support = facing_up(top) ? support_of(side) : -1;
      // The top above the support: the edge's middle, on the top, lies that high over it.
      if (support >= 0 &&
          model->FacePlane(support).SignedDistance(0.5 * (e.start + e.end)) < config.two_face_min_height) {
        support = -1;
      }
    }
    if (support < 0 || support == a || support == b) continue;
    const int ra = Find(group, a), rb = Find(group, b);
    const int root = std::min(ra, rb);
    group[std::max(ra, rb)] = root;
    const int kept_support = support_of_group[ra] >= 0 ? support_of_group[ra] : support_of_group[rb];
    support_of_group[root] = kept_support >= 0 ? kept_support : support;
  }
  std::vector<int> object_of_group(n, -1);
  for (int p = 0; p < static_cast<int>(n); ++p) {
    const int root = Find(group, face(p));
    if (support_of_group[root] < 0 || model->structure[p] || face(p) == support_of_group[root]) continue;
    if (object_of_group[root] < 0) {
      object_of_group[root] = static_cast<int>(model->objects.size());
      model->objects.emplace_back();
      model->objects.back().support = support_of_group[root];
    }
    model->objects[object_of_group[root]].planes.push_back(p);  // every piece of each face, ascending
  }
}

}  // namespace planemap
