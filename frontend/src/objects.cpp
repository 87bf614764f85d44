#include "planemap/frontend/objects.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "planemap/core/error.h"
#include "planemap/core/statistics.h"
#include "planemap/frontend/intersections.h"

namespace planemap {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

std::pair<std::string, std::string> SplitEdge(const std::string& edge) {
  const size_t dash = edge.find('-');
  if (dash == std::string::npos) return {"", ""};
  return {edge.substr(0, dash), edge.substr(dash + 1)};
}

struct Matcher {
  const GraphPattern& pattern;
  const FrameModel& model;
  std::vector<int> graph;                      // plane ids: the object's faces and the floor
  std::vector<std::string> orientation;        // per graph node
  std::vector<std::pair<int, int>> edges;      // pattern edges as node indices
  std::vector<int> assignment;                 // pattern node -> graph node

  int support = -1;                            // plane id of the object's support, -1: none

  bool Fits(size_t node, int g) const {
    const std::string& want = pattern.nodes[node].orientation;
    if (want == "support" ? graph[g] != support : (want != "any" && want != orientation[g])) return false;
    if (std::find(assignment.begin(), assignment.begin() + node, g) != assignment.begin() + node) return false;
    for (const auto& [a, b] : edges) {  // edges to nodes already placed
      const size_t other = a == static_cast<int>(node) ? b : (b == static_cast<int>(node) ? a : node);
      if (other == node || other > node) continue;
      if (model.EdgeBetween(graph[g], graph[assignment[other]]) < 0) return false;
    }
    return true;
  }
  bool Search(size_t node) {
    if (node == pattern.nodes.size()) return true;
    for (int g = 0; g < static_cast<int>(graph.size()); ++g) {
      if (!Fits(node, g)) continue;
      assignment[node] = g;
      if (Search(node + 1)) return true;
    }
    return false;
  }
};

// The floor, or a piece of it (FindFaces).
bool OnFloor(const FrameModel& model, int plane) {
  return model.floor >= 0 && model.FaceOf(plane) == model.FaceOf(model.floor);
}

std::string Orientation(const FrameModel& model, int plane, const Eigen::Vector3d& up, double tolerance) {
  if (OnFloor(model, plane)) return "floor";
  const double c = std::abs(model.planes[plane].plane.normal.dot(up));
  if (c > std::cos(tolerance)) return "horizontal";
  if (c < std::sin(tolerance)) return "vertical";
  return "slanted";
}

// Pieces of one edge (ObjectConfig::edge_join_*), joined two at a time until no two are left:
// the two measure one axis (axis_of(direction), the same and not -1) and share a plane, the
// shorter piece's ends lie on the longer one's line, and their stretches along that line overlap
// or leave a gap of at most edge_join_gap. The joined edge runs along the longer piece's line
// from the lower of the two ends to the higher, each end cut as the piece it came from is cut
// there (a complete end within edge_length_tolerance of a cut one that goes on past it stands).
template <class AxisOf>
void JoinEdgePieces(const ObjectConfig& config, AxisOf&& axis_of, std::vector<PlaneEdge>* edges) {
  if (config.edge_join_distance <= 0.0) return;
  struct End {
    double t;  // along the longer piece's line [m]
    bool cut;
  };
  bool joined = true;
  while (joined) {
    joined = false;
    for (size_t i = 0; i < edges->size() && !joined; ++i) {
      for (size_t j = i + 1; j < edges->size() && !joined; ++j) {
        const PlaneEdge& a = (*edges)[i];
        const PlaneEdge& b = (*edges)[j];
        const bool share = a.plane_a == b.plane_a || a.plane_a == b.plane_b || a.plane_b == b.plane_a ||
                           a.plane_b == b.plane_b;
        const int axis = axis_of(a.direction);
        const PlaneEdge& longer = a.length >= b.length ? a : b;
        const PlaneEdge& shorter = a.length >= b.length ? b : a;
        const Eigen::ParametrizedLine<double, 3> line(longer.start, longer.direction);
        if (!share || axis < 0 || axis_of(b.direction) != axis ||
            line.distance(shorter.start) > config.edge_join_distance ||
            line.distance(shorter.end) > config.edge_join_distance) {
          continue;
        }
        auto ends = [&](const PlaneEdge& e) {
          const End s{longer.direction.dot(e.start - longer.start), e.start_cut};
          const End t{longer.direction.dot(e.end - longer.start), e.end_cut};
          return s.t <= t.t ? std::make_pair(s, t) : std::make_pair(t, s);
        };
        const auto [a_low, a_high] = ends(longer);
        const auto [b_low, b_high] = ends(shorter);
        if (std::max(b_low.t - a_high.t, a_low.t - b_high.t) > config.edge_join_gap) continue;
        // Each end the farther of the two pieces', but a complete end stands against a cut one
        // that goes on past it only by edge_length_tolerance (noise, as for whole edges below).
        const auto pick = [&](const End& farther, const End& other) {
          return farther.cut && !other.cut && std::abs(farther.t - other.t) <= config.edge_length_tolerance ? other : farther;
        };
        const End low = b_low.t < a_low.t ? pick(b_low, a_low) : pick(a_low, b_low);
        const End high = b_high.t > a_high.t ? pick(b_high, a_high) : pick(a_high, b_high);
        PlaneEdge piece = longer;
        piece.start = longer.start + low.t * longer.direction;
        piece.end = longer.start + high.t * longer.direction;
        piece.direction = longer.direction;
        piece.length = high.t - low.t;
        piece.start_cut = low.cut;
        piece.end_cut = high.cut;
        piece.points = a.points + b.points;
        (*edges)[i] = piece;
        edges->erase(edges->begin() + static_cast<std::ptrdiff_t>(j));
        joined = true;
      }
    }
  }
}

// Whether the camera sees past the end of a face's points at `end` along unit `dir` (ObjectConfig::
// face_end_*): `mask` marks the face's pixels in the organized cloud.
bool SeesPastEnd(const Cloud& cloud, const std::vector<char>& mask, const std::vector<int>& inliers,
                 const Plane& plane, const Eigen::Vector3d& dir, double end, const ObjectConfig& config) {
  if (cloud.height <= 1) return false;  // not organized: nothing to look past
  const int width = static_cast<int>(cloud.width), height = static_cast<int>(cloud.height);
  // Which way the end lies in the image: the gradient of the distance along dir over the face's
  // pixels (least squares, t = a u + b v + c); only the directions within 60 deg of it look past it.
  Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (int i : inliers) {
    const Eigen::Vector3d row(i % width, i / width, 1.0);
    normal_matrix += row * row.transpose();
    rhs += row * dir.dot(cloud[i].getVector3fMap().cast<double>());
  }
  const Eigen::Vector3d fit = normal_matrix.ldlt().solve(rhs);
  Eigen::Vector2d outward(fit[0], fit[1]);
  // That gradient is how far the face runs along dir per pixel: a face seen at a glancing angle
  // (a top a few rows high from far away) places its end no finer than that.
  if (!outward.allFinite() || outward.norm() == 0.0 || outward.norm() > config.face_end_max_pixel) return false;
  outward.normalize();
  int free = 0, hidden = 0, undecided = 0;
  for (int i : inliers) {
    const Eigen::Vector3d x = cloud[i].getVector3fMap().cast<double>();
    if (dir.dot(x) < end - config.face_end_band) continue;
    const int u = i % width, v = i / width;
    for (int du = -1; du <= 1; ++du) {
      for (int dv = -1; dv <= 1; ++dv) {
        if ((du == 0 && dv == 0) || Eigen::Vector2d(du, dv).normalized().dot(outward) < 0.5) continue;
        // The first pixel with depth beyond the face's own (and beyond its unsegmented fringe on
        // its plane, and a silhouette's missing depth) decides; none within face_end_search: the
        // face may go on unseen.
        bool decided = false, left_face = false;
        for (int step = 1; step <= config.face_end_search && !decided; ++step) {
          const int qu = u + step * du, qv = v + step * dv;
          if (qu < 0 || qv < 0 || qu >= width || qv >= height) {
            decided = true;  // the image ends: the face may go on out of view
            ++hidden;
            break;
          }
          const int q = qv * width + qu;
          if (mask[q]) continue;
          left_face = true;
          if (!IsValidPoint(cloud[q])) continue;
          const Eigen::Vector3d y = cloud[q].getVector3fMap().cast<double>();
          const Eigen::Vector3d on_plane = AlongRayOntoPlane(plane, y);
          if (dir.dot(on_plane) <= dir.dot(x)) {
            decided = true;  // not beyond the end: no vote
            continue;
          }
          const double behind = y.norm() - on_plane.norm();
          if (std::abs(behind) < config.face_end_gap) continue;  // the face's plane goes on
          decided = true;
          (behind > 0.0 ? free : hidden) += 1;  // the camera sees past the face, or something hides it
        }
        if (!decided && left_face) ++undecided;
      }
    }
  }
  // Whole: the camera sees past the end where it sees anything there, and past a quarter of it at
  // least (the rest may have no depth: a silhouette's shadow, a background out of range).
  return free > 0 && free >= config.face_end_free_share * (free + hidden) &&
         free >= config.face_end_min_seen * (free + hidden + undecided);
}

// One end of an object's extent along an axis.
struct AxisEnd {
  double at = 0.0;     // along the axis [m]
  bool whole = false;  // the object ends there
  bool plane = false;  // on a bounding plane (a face across the axis, or the support)
};

// Steps 2 (the axes no edge measured) and 3 for an object of two faces (FrameObject::support): along
// each axis, each end on a face across it (the object lies behind its faces: normals point to the
// camera) or on the support (the object lies above it); else at the end of the points of the faces
// along it, whole when the camera sees past it. Both ends on planes, or no complete edge: the
// dimension is theirs. The centre lies halfway between the ends.
void MeasureTwoFaceObject(const Cloud& cloud, const ObjectConfig& config, const FrameModel& model,
                          FrameObject* object) {
  const double axis_cos = std::cos(config.axis_tolerance_deg * kDegToRad);
  const double along_sin = std::sin(config.axis_tolerance_deg * kDegToRad);
  std::vector<char> mask(cloud.size(), 0);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  // Where a bounding plane lies along an axis is read beneath (or behind) the object's faces'
  // centroid: a plane a few degrees off the axis lies elsewhere further away.
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();
  for (int p : object->planes) reference += model.planes[p].centroid;
  reference /= static_cast<double>(object->planes.size());
  std::map<int, std::vector<int>> face_inliers;  // every piece's
  for (int p : object->planes) {
    std::vector<int>& inliers = face_inliers[model.FaceOf(p)];
    inliers.insert(inliers.end(), model.planes[p].inliers.begin(), model.planes[p].inliers.end());
  }
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = object->axes.col(k);
    std::optional<AxisEnd> low, high;
    auto bound = [&](const Plane& plane, bool object_in_front) {
      const double c = plane.normal.dot(a);
      if (std::abs(c) < axis_cos) return;
      const AxisEnd end{a.dot(reference) - plane.SignedDistance(reference) / c, true, true};
      // The object lies on the side of the plane its normal points to (the support) or away from it.
      ((c > 0) == object_in_front ? low : high) = end;
    };
    for (const auto& [f, inliers] : face_inliers) bound(model.FacePlane(f), false);
    bound(model.FacePlane(object->support), true);
    // The faces running along the axis: their points' extent.
    std::optional<AxisEnd> seen_low, seen_high;
    for (const auto& [f, inliers] : face_inliers) {
      if (std::abs(model.FacePlane(f).normal.dot(a)) > along_sin || inliers.empty()) continue;
      std::vector<double> t;
      t.reserve(inliers.size());
      for (int i : inliers) {
        t.push_back(a.dot(cloud[i].getVector3fMap().cast<double>()));
        mask[i] = 1;
      }
      std::sort(t.begin(), t.end());
      const double lo = SortedPercentile(t, config.face_extent_trim), hi = SortedPercentile(t, 1.0 - config.face_extent_trim);
      // The face as the cuboid has it: its normal along the object's axis nearest to it, through its
      // points' centroid (a face seen as a thin strip is fitted a few degrees off, and its plane
      // continued past its end would pass above or below the rest of the face).
      const Eigen::Vector3d n = model.FacePlane(f).normal;
      int nearest = 0;
      (object->axes.transpose() * n).cwiseAbs().maxCoeff(&nearest);
      const Eigen::Vector3d axis = object->axes.col(nearest) * (object->axes.col(nearest).dot(n) > 0.0 ? 1.0 : -1.0);
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (int i : inliers) centroid += cloud[i].getVector3fMap().cast<double>();
      const Plane plane = Plane::FromPointNormal(centroid / static_cast<double>(inliers.size()), axis);
      if (!seen_low || lo < seen_low->at) seen_low = AxisEnd{lo, SeesPastEnd(cloud, mask, inliers, plane, -a, -lo, config), false};
      if (!seen_high || hi > seen_high->at) seen_high = AxisEnd{hi, SeesPastEnd(cloud, mask, inliers, plane, a, hi, config), false};
      for (int i : inliers) mask[i] = 0;
    }
    if (!low) low = seen_low;
    if (!high) high = seen_high;
    if (!low || !high || high->at <= low->at) {
      centre[k] = low ? low->at : (high ? high->at : 0.0);
      continue;
    }
    const double length = high->at - low->at;
    const bool complete = low->whole && high->whole;
    const bool exact = low->plane && high->plane;
    const bool edge_complete = object->dimension_complete[k] && object->dimensions[k] > 0.0;
    // A cut edge longer by more than edge_length_tolerance shows the object goes on past the
    // ends seen (as for edges, MeasureObjects step 2).
    const bool beyond = !edge_complete && object->dimensions[k] > length + config.edge_length_tolerance;
    if (exact || (!edge_complete && !beyond && (complete || length > object->dimensions[k]))) {
      object->dimensions[k] = length;
      object->dimension_complete[k] = complete;
    }
    // The centre: half the dimension in from a bounding plane, else the middle of what is seen.
    const double half = 0.5 * object->dimensions[k];
    centre[k] = low->plane ? low->at + half : (high->plane ? high->at - half : 0.5 * (low->at + high->at));
  }
  object->center = object->axes * centre;
}

}  // namespace

PatternsConfig LoadPatterns(const std::string& file) {
  PatternsConfig config = LoadConfigFile<PatternsConfig>(file);
  // Orientations are checked as the file is read (PatternNode's OneOf), with their line.
  if (config.patterns.empty()) ThrowInputError(file, 0, "no patterns: list at least one under 'patterns:' (see configs/patterns.yaml)");
  for (size_t i = 0; i < config.patterns.size(); ++i) {
    const GraphPattern& p = config.patterns[i];
    const std::string where = "patterns[" + std::to_string(i) + "]";
    if (p.class_name.empty()) ThrowInputError(file, 0, where + " has no 'class'");
    if (p.nodes.empty()) ThrowInputError(file, 0, where + " (" + p.class_name + ") has no nodes");
    std::set<std::string> names;
    for (const PatternNode& n : p.nodes) {
      if (!names.insert(n.name).second) ThrowInputError(file, 0, where + ": duplicate node '" + n.name + "'");
    }
    for (const std::string& e : p.edges) {
      const auto [a, b] = SplitEdge(e);
      if (!names.count(a) || !names.count(b)) {
        ThrowInputError(file, 0, where + " (" + p.class_name + "): edge '" + e + "' must join two of its nodes as 'a-b'");
      }
    }
  }
  return config;
}

double ObjectHeight(const Cloud& cloud, const FrameModel& model, const FrameObject& object, const Eigen::Vector3d& up) {
  std::vector<double> heights;
  size_t total = 0;
  for (int p : object.planes) total += model.planes[p].inliers.size();
  heights.reserve(total);
  for (int p : object.planes) {
    for (int i : model.planes[p].inliers) {
      const Eigen::Vector3d x = cloud[i].getVector3fMap().cast<double>();
      heights.push_back(model.floor >= 0 ? model.planes[model.floor].plane.SignedDistance(x) : up.dot(x));
    }
  }
  if (heights.empty()) return 0.0;
  const size_t k = std::min(heights.size() - 1, static_cast<size_t>(0.99 * heights.size()));
  std::nth_element(heights.begin(), heights.begin() + k, heights.end());
  const double top = heights[k];
  if (model.floor >= 0) return top;
  const size_t j = static_cast<size_t>(0.01 * heights.size());
  std::nth_element(heights.begin(), heights.begin() + j, heights.end());
  return top - heights[j];
}

void ClassifyObjects(const PatternsConfig& patterns, const ObjectConfig& config,
                     const Eigen::Vector3d& up, FrameModel* model) {
  for (FrameObject& object : model->objects) {
    object.label = "unknown";
    std::vector<int> graph = object.planes;
    // The floor's pieces (FindFaces): a side may meet the floor in one of them.
    for (int p = 0; p < static_cast<int>(model->planes.size()); ++p) {
      if (OnFloor(*model, p)) graph.push_back(p);
    }
    if (object.support >= 0 && std::find(graph.begin(), graph.end(), object.support) == graph.end()) graph.push_back(object.support);
    // An object of two faces is upright on its support.
    const Eigen::Vector3d object_up = object.support >= 0 ? model->FacePlane(object.support).normal : up;
    std::vector<std::string> orientation;
    for (int p : graph) orientation.push_back(Orientation(*model, p, object_up, config.orientation_tolerance_deg * kDegToRad));
    // The height is known when the top is seen or a vertical edge is complete; otherwise the
    // object may go on beyond the image and its height only bounds the true one from below.
    const double height = object.height;
    object.height_known = object.dimension_complete[2];
    for (size_t g = 0; g < graph.size(); ++g) {
      object.height_known = object.height_known || (orientation[g] == "horizontal" && graph[g] != object.support);
    }
    const bool height_known = object.height_known;
    for (const GraphPattern& pattern : patterns.patterns) {
      if (pattern.max_height > 0 && (height > pattern.max_height || !height_known)) continue;
      if (pattern.min_height > 0 && height < pattern.min_height && height_known) continue;
      Matcher matcher{pattern, *model, graph, orientation, {}, std::vector<int>(pattern.nodes.size(), -1), object.support};
      for (const std::string& e : pattern.edges) {
        const auto [a, b] = SplitEdge(e);
        int ia = -1, ib = -1;
        for (size_t n = 0; n < pattern.nodes.size(); ++n) {
          if (pattern.nodes[n].name == a) ia = static_cast<int>(n);
          if (pattern.nodes[n].name == b) ib = static_cast<int>(n);
        }
        matcher.edges.emplace_back(ia, ib);
      }
      if (matcher.Search(0)) {
        object.label = pattern.class_name;
        break;
      }
    }
  }
}

void MeasureObjects(const Cloud& cloud, const ObjectConfig& config, const Eigen::Vector3d& up_prior, FrameModel* model) {
  const Eigen::Vector3d scene_up = model->floor >= 0 ? model->planes[model->floor].plane.normal : up_prior.normalized();
  const double axis_cos = std::cos(config.axis_tolerance_deg * kDegToRad);
  const double vertical_sin = std::sin(config.axis_tolerance_deg * kDegToRad);
  for (FrameObject& object : model->objects) {
    // 1. Axes: z up, x the horizontal normal of the largest vertical face (a face in pieces:
    //    its plane fitted to them all, FindFaces, and its size theirs). Without a floor, up is
    //    the normal of the object's own face nearest the prior's up, when one lies within
    //    max_up_tilt_deg of it: a hand-held camera rolls, and its up is not the object's.
    std::map<int, size_t> face_size;
    for (int p : object.planes) face_size[model->FaceOf(p)] += model->planes[p].inliers.size();
    const bool two_faces = object.angles.empty() && object.support >= 0;
    Eigen::Vector3d up = two_faces ? model->FacePlane(object.support).normal : scene_up;
    if (model->floor < 0 && !two_faces) {
      double best = std::cos(config.max_up_tilt_deg * kDegToRad);
      for (const auto& [f, size] : face_size) {
        const Eigen::Vector3d& n = model->FacePlane(f).normal;
        if (std::abs(n.dot(scene_up)) > best) {
          best = std::abs(n.dot(scene_up));
          up = n.dot(scene_up) > 0.0 ? n : Eigen::Vector3d(-n);
        }
      }
    }
    int largest = -1;
    for (const auto& [f, size] : face_size) {
      if (std::abs(model->FacePlane(f).normal.dot(up)) > vertical_sin) continue;
      if (largest < 0 || size > face_size[largest]) largest = f;
    }
    Eigen::Vector3d x = largest >= 0 ? model->FacePlane(largest).normal : up.unitOrthogonal();
    x = (x - x.dot(up) * up).normalized();
    object.axes.col(0) = x;
    object.axes.col(1) = up.cross(x);
    object.axes.col(2) = up;

    // 2. Dimensions: the longest edge along each axis, complete edges first, unless an edge cut
    //    by the image or an occluder is longer by more than edge_length_tolerance: the object
    //    then reaches at least that far, and the complete edge (a face split in two, say) is not
    //    its whole extent.
    std::set<int> members(object.planes.begin(), object.planes.end());
    for (int p = 0; p < static_cast<int>(model->planes.size()); ++p) {
      if (OnFloor(*model, p)) members.insert(p);
    }
    if (object.support >= 0) members.insert(object.support);
    object.dimensions.setZero();
    object.dimension_complete = {false, false, false};
    auto axis_of = [&](const Eigen::Vector3d& d) {
      for (int k = 0; k < 3; ++k) {
        if (std::abs(d.dot(object.axes.col(k))) > axis_cos) return k;
      }
      return -1;
    };
    std::vector<PlaneEdge> edges;
    for (const PlaneEdge& e : model->edges) {
      if (members.count(e.plane_a) && members.count(e.plane_b)) edges.push_back(e);
    }
    JoinEdgePieces(config, axis_of, &edges);
    Eigen::Vector3d longest_cut = Eigen::Vector3d::Zero();
    for (const PlaneEdge& e : edges) {
      if (OnFloor(*model, e.plane_a) && OnFloor(*model, e.plane_b)) continue;
      const int k = axis_of(e.direction);
      if (k < 0) continue;
      if (!e.Complete()) longest_cut[k] = std::max(longest_cut[k], e.length);
      const bool better = e.Complete() ? (!object.dimension_complete[k] || e.length > object.dimensions[k])
                                       : (!object.dimension_complete[k] && e.length > object.dimensions[k]);
      if (better) {
        object.dimensions[k] = e.length;
        object.dimension_complete[k] = e.Complete();
      }
    }
    for (int k = 0; k < 3; ++k) {
      if (object.dimension_complete[k] && longest_cut[k] > object.dimensions[k] + config.edge_length_tolerance) {
        object.dimensions[k] = longest_cut[k];
        object.dimension_complete[k] = false;
      }
    }

    // 3. Centre, eq. (7): C = T_c + (e1 + e2 + e3) / 2 for each trihedral angle, with e_i the
    //    edges leaving the corner, as long as the object's dimension along them; then the mean.
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    for (int a : object.angles) {
      const TrihedralAngle& angle = model->angles[a];
      Eigen::Vector3d c = angle.corner;
      for (int e : angle.edges) {
        const PlaneEdge& edge = model->edges[e];
        const bool from_start = (edge.start - angle.corner).norm() < (edge.end - angle.corner).norm();
        const Eigen::Vector3d away = from_start ? edge.direction : -edge.direction;
        const int k = axis_of(edge.direction);
        const double length = k >= 0 && object.dimensions[k] > 0 ? object.dimensions[k] : edge.length;
        c += 0.5 * length * away;
      }
      sum += c;
      ++count;
    }
    object.center = count > 0 ? Eigen::Vector3d(sum / count) : Eigen::Vector3d::Zero();
    if (two_faces) MeasureTwoFaceObject(cloud, config, *model, &object);

    // 4. Grasp sides: vertical faces across which the object is as wide as the hands can span,
    //    on an object low enough; the chosen side is the one facing the camera most.
    object.grasp_sides.clear();
    object.grasp_side = -1;
    object.grasp_axis.setZero();
    object.height = ObjectHeight(cloud, *model, object, up);
    double best_facing = -1.0;
    for (const auto& [p, size] : face_size) {
      const Plane& face = model->FacePlane(p);
      if (std::abs(face.normal.dot(up)) > vertical_sin) continue;
      const int k = axis_of(face.normal);
      if (k < 0 || k == 2) continue;
      const double span = object.dimensions[k];
      if (span < config.hand_span_min || span > config.hand_span_max || object.height > config.grasp_max_height) continue;
      object.grasp_sides.push_back(p);
      const double facing = face.normal.dot(-model->planes[p].centroid.normalized());
      if (facing > best_facing) {
        best_facing = facing;
        object.grasp_side = p;
        object.grasp_axis = face.normal;
      }
    }
  }
  // A cuboid is measured along each of its axes, whole or in part; planes meeting at a corner whose
  // edges run along none of them (a slanted sheet against a wall, a tilted lid) are not one.
  const auto unmeasured = [](const FrameObject& o) { return (o.dimensions.array() <= 0.0).any(); };
  model->objects.erase(std::remove_if(model->objects.begin(), model->objects.end(), unmeasured), model->objects.end());
}

}  // namespace planemap
