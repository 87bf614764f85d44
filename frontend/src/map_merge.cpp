#include "planemap/frontend/map_merge.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <unordered_set>

namespace planemap {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Where a landmark's surface is: the mean of its inliers, else of its voxel points.
Eigen::Vector3d Centroid(const PlaneLandmark& l) {
  if (l.moments.w > 0.0) return l.moments.Mean();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3f& p : l.points) sum += p.cast<double>();
  return l.points.empty() ? Eigen::Vector3d(-l.plane.offset * l.plane.normal) : Eigen::Vector3d(sum / l.points.size());
}

bool SameSurface(const PlaneLandmark& a, const PlaneLandmark& b, const MapMergeConfig& config) {
  return NormalAngle(a.plane, b.plane) <= config.fuse_max_angle_deg * kDegToRad &&
         std::abs(a.plane.SignedDistance(Centroid(b))) <= config.fuse_max_distance &&
         std::abs(b.plane.SignedDistance(Centroid(a))) <= config.fuse_max_distance &&
         a.Overlaps(b.low, b.high, config.fuse_overlap_margin);
}

// The map axis of `axes` most parallel to `direction`.
int AxisOf(const Eigen::Matrix3d& axes, const Eigen::Vector3d& direction) {
  int k = 0;
  (axes.transpose() * direction).cwiseAbs().maxCoeff(&k);
  return k;
}

// Adds `from`'s observations (complete edge lengths, centres, votes) to `into`, axis by axis.
void Absorb(const MapObject& from, MapObject* into) {
  into->observations += from.observations;
  for (int j = 0; j < 3; ++j) {
    const int k = AxisOf(into->axes, from.axes.col(j));
    into->complete_count[k] += from.complete_count[j];
    into->complete_sum[k] += from.complete_sum[j];
  }
  into->center_count += from.center_count;
  into->center_sum += from.center_sum;
  into->partial_center_count += from.partial_center_count;
  into->partial_center_sum += from.partial_center_sum;
  for (const auto& [label, n] : from.label_votes) Vote(&into->label_votes, label, n);
  for (const auto& [landmark, n] : from.grasp_votes) Vote(&into->grasp_votes, landmark, n);
}

// Folds `from` into `into`, one physical object seen as two: evidence added (Absorb), faces
// united, and the estimates made again from the sums. A dimension is the mean of the complete
// views, else the longer of the two lower bounds.
void Fold(const MapObject& from, const PlaneMap& map, MapObject* into) {
  Absorb(from, into);
  std::set<int> faces(into->landmarks.begin(), into->landmarks.end());
  faces.insert(from.landmarks.begin(), from.landmarks.end());
  into->landmarks.assign(faces.begin(), faces.end());
  for (int j = 0; j < 3; ++j) {
    const int k = AxisOf(into->axes, from.axes.col(j));
    if (into->complete_count[k] > 0) {
      into->dimensions[k] = into->complete_sum[k] / into->complete_count[k];
      into->dimension_complete[k] = true;
    } else {
      into->dimensions[k] = std::max(into->dimensions[k], from.dimensions[j]);
    }
  }
  into->center = into->center_count > 0 ? Eigen::Vector3d(into->center_sum / into->center_count)
                                        : Eigen::Vector3d(into->partial_center_sum / std::max(1, into->partial_center_count));
  if (!into->label_votes.empty()) into->label = Winner(into->label_votes);
  if (!into->grasp_votes.empty()) {
    into->grasp_landmark = Winner(into->grasp_votes);
    into->has_grasp_axis = true;
    into->grasp_axis = map.landmarks[into->grasp_landmark].plane.normal;
  }
}

// Renumbers landmarks: new_id[old] is the landmark it became (several olds may share one).
// Landmarks, edges (the longest of a merged pair) and objects' faces and votes follow.
void Renumber(const std::vector<int>& new_id, double voxel, PlaneMap* map) {
  const int count = new_id.empty() ? 0 : *std::max_element(new_id.begin(), new_id.end()) + 1;
  std::vector<PlaneLandmark> landmarks(count);
  std::vector<std::unordered_set<long long>> voxels(count);
  std::vector<int> members(count, 0);
  for (size_t old = 0; old < map->landmarks.size(); ++old) {
    const PlaneLandmark& from = map->landmarks[old];
    const int id = new_id[old];
    PlaneLandmark& l = landmarks[id];
    if (members[id]++ == 0) {
      l.id = id;
      l.plane = from.plane;
      l.first_frame = from.first_frame;
      l.last_frame = from.last_frame;
    }
    l.first_frame = std::min(l.first_frame, from.first_frame);
    l.last_frame = std::max(l.last_frame, from.last_frame);
    l.moments += from.moments;
    l.low = l.low.cwiseMin(from.low);
    l.high = l.high.cwiseMax(from.high);
    l.observations += from.observations;
    l.floor_votes += from.floor_votes;
    for (const Eigen::Vector3f& p : from.points) {
      if (voxels[id].insert(VoxelKey(p, voxel)).second) l.points.push_back(p);
    }
  }
  // A fused landmark's plane from all its inliers, its normal kept on the cameras' side.
  for (PlaneLandmark& l : landmarks) {
    if (members[l.id] < 2) continue;
    const PlaneFit fit = FitPlane(l.moments);
    if (fit.ok) l.plane = fit.plane.normal.dot(l.plane.normal) >= 0.0 ? fit.plane : fit.plane.Flipped();
  }
  std::vector<MapEdge> edges;
  for (MapEdge e : map->edges) {
    int a = new_id[e.landmark_a], b = new_id[e.landmark_b];
    if (a == b) continue;
    if (a > b) std::swap(a, b);
    e.landmark_a = a;
    e.landmark_b = b;
    auto it = std::find_if(edges.begin(), edges.end(), [&](const MapEdge& m) { return m.landmark_a == a && m.landmark_b == b; });
    if (it == edges.end()) {
      edges.push_back(e);
      continue;
    }
    // The merged edge is the longest of the pair (paper, Fig. 4).
    if (e.length > it->length) {
      it->start = e.start;
      it->end = e.end;
      it->length = e.length;
    }
    it->complete = it->complete || e.complete;
    it->observations += e.observations;
    it->convex_views += e.convex_views;
    it->concave_views += e.concave_views;
  }
  for (MapObject& o : map->objects) {
    std::set<int> faces;
    for (int f : o.landmarks) faces.insert(new_id[f]);
    o.landmarks.assign(faces.begin(), faces.end());
    std::vector<std::pair<int, int>> votes;
    for (const auto& [landmark, n] : o.grasp_votes) Vote(&votes, new_id[landmark], n);
    o.grasp_votes = votes;
    if (o.grasp_landmark >= 0) o.grasp_landmark = new_id[o.grasp_landmark];
    if (o.x_landmark >= 0) o.x_landmark = new_id[o.x_landmark];
  }
  map->landmarks = std::move(landmarks);
  map->edges = std::move(edges);
}

// The map's graph as a FrameModel in the world frame: planes = landmarks (their inliers index
// their voxel points in `cloud`), edges = map edges (an edge never seen whole counts as cut).
FrameModel MapGraph(const PlaneMap& map, const PlaneGraphConfig& config, Cloud* cloud) {
  FrameModel model;
  for (const PlaneLandmark& l : map.landmarks) {
    DetectedPlane p;
    p.id = l.id;
    p.plane = l.plane;
    p.centroid = Centroid(l);
    for (const Eigen::Vector3f& x : l.points) {
      pcl::PointXYZRGB q;
      q.getVector3fMap() = x;
      p.inliers.push_back(static_cast<int>(cloud->size()));
      cloud->push_back(q);
    }
    model.planes.push_back(std::move(p));
  }
  for (const MapEdge& m : map.edges) {
    PlaneEdge e;
    e.plane_a = m.landmark_a;
    e.plane_b = m.landmark_b;
    e.start = m.start;
    e.end = m.end;
    e.length = m.length;
    e.length_eq6 = m.length;
    e.direction = (m.end - m.start).norm() > 0.0 ? Eigen::Vector3d((m.end - m.start).normalized()) : Eigen::Vector3d::UnitX();
    e.start_cut = e.end_cut = !m.complete;
    e.convex = m.Convex();
    model.edges.push_back(e);
  }
  model.floor = map.Floor();
  model.structure.resize(map.landmarks.size());
  for (const PlaneLandmark& l : map.landmarks) {
    model.structure[l.id] = l.id == model.floor || l.Extent() > config.structure_min_extent;
  }
  return model;
}

}  // namespace

int FuseDuplicateLandmarks(const MapMergeConfig& config, PlaneMap* map) {
  ValidateConfig(config, "merge.");
  const int n = static_cast<int>(map->landmarks.size());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      if (SameSurface(map->landmarks[a], map->landmarks[b], config)) parent[Find(parent, b)] = Find(parent, a);
    }
  }
  // Dense new ids in the order of each group's first landmark.
  std::vector<int> new_id(n, -1), id_of_root(n, -1);
  int next = 0;
  for (int i = 0; i < n; ++i) {
    const int root = Find(parent, i);
    if (id_of_root[root] < 0) id_of_root[root] = next++;
    new_id[i] = id_of_root[root];
  }
  Renumber(new_id, config.landmark_voxel, map);
  return n - next;
}

int FuseDuplicateObjects(const MapMergeConfig& config, PlaneMap* map) {
  ValidateConfig(config, "merge.");
  std::vector<MapObject> kept;
  int folded = 0;
  for (const MapObject& o : map->objects) {
    if (o.structure) continue;  // no object (MapObject::structure); ids are renumbered here anyway
    auto same = std::find_if(kept.begin(), kept.end(), [&](const MapObject& k) {
      return CuboidOverlap(k.center, k.axes, k.dimensions, o.center, o.axes, o.dimensions) >= config.fuse_object_overlap;
    });
    if (same == kept.end()) {
      kept.push_back(o);
      kept.back().id = static_cast<int>(kept.size()) - 1;
      continue;
    }
    ++folded;
    MapObject& into = *same;
    Fold(o, *map, &into);
    into.uncertainty = MapObject::Uncertainty{};  // of neither object any more
  }
  map->objects = std::move(kept);
  return folded;
}

void RebuildObjects(const ObjectModel& model, double object_match_distance, PlaneMap* map) {
  Cloud cloud;
  FrameModel graph = MapGraph(*map, model.graph, &cloud);
  AggregateObjects(cloud, model.graph, &graph);
  // Up: the floor's normal, else the configured camera up in the first keyframe's camera.
  Eigen::Vector3d up = UpPrior(model.graph);
  if (graph.floor >= 0) {
    up = graph.planes[graph.floor].plane.normal;
  } else if (!map->keyframes.empty()) {
    up = map->keyframes.front().T_world_camera.linear() * up;
  }
  MeasureObjects(cloud, model.objects, up, &graph);
  ClassifyObjects(model.patterns, model.objects, up, &graph);

  // Each old object passes its observations to the rebuilt object it shares the most faces with
  // (two at least), else to the nearest within object_match_distance.
  std::vector<int> heir(map->objects.size(), -1);
  for (size_t k = 0; k < map->objects.size(); ++k) {
    const MapObject& old = map->objects[k];
    if (old.structure) continue;  // no object: its views are a wall's (MapObject::structure)
    int best_shared = 1;
    double best_distance = object_match_distance;
    for (size_t j = 0; j < graph.objects.size(); ++j) {
      const FrameObject& fo = graph.objects[j];
      int shared = 0;
      for (int f : old.landmarks) shared += std::count(fo.planes.begin(), fo.planes.end(), f) > 0;
      const double distance = (old.center - fo.center).norm();
      if (shared > best_shared || (best_shared < 2 && distance < best_distance)) {
        heir[k] = static_cast<int>(j);
        best_shared = std::max(best_shared, shared);
        best_distance = distance;
      }
    }
  }
  std::vector<MapObject> rebuilt;
  for (size_t j = 0; j < graph.objects.size(); ++j) {
    const FrameObject& fo = graph.objects[j];
    MapObject mo;
    mo.id = static_cast<int>(rebuilt.size());
    mo.landmarks = fo.planes;
    mo.axes = fo.axes;
    for (size_t k = 0; k < map->objects.size(); ++k) {
      if (heir[k] == static_cast<int>(j)) Absorb(map->objects[k], &mo);
    }
    // Class: the merged graph's, when it measured the height (paper: re-classified); else what
    // the views voted.
    mo.label = fo.height_known || mo.label_votes.empty() ? fo.label : Winner(mo.label_votes);
    // Dimensions: the mean of the views that saw an edge whole, else the graph's longest edge.
    for (int k = 0; k < 3; ++k) {
      if (mo.complete_count[k] > 0) {
        mo.dimensions[k] = mo.complete_sum[k] / mo.complete_count[k];
        mo.dimension_complete[k] = true;
      } else {
        mo.dimensions[k] = fo.dimensions[k];
        mo.dimension_complete[k] = fo.dimension_complete[k];
      }
    }
    mo.center = mo.center_count > 0 ? Eigen::Vector3d(mo.center_sum / mo.center_count) : fo.center;
    for (int f : mo.landmarks) {
      if (std::abs(fo.axes.col(0).dot(map->landmarks[f].plane.normal)) > 0.99) mo.x_landmark = f;
    }
    // Grasp side: the views' choice, else the graph's.
    mo.grasp_landmark = !mo.grasp_votes.empty() ? Winner(mo.grasp_votes) : fo.grasp_side;
    if (mo.grasp_landmark >= 0) {
      mo.has_grasp_axis = true;
      mo.grasp_axis = map->landmarks[mo.grasp_landmark].plane.normal;
    }
    rebuilt.push_back(std::move(mo));
  }
  // Objects the merged graph does not form (a corner never seen whole in one map) stay; one seen
  // in both maps (two shared faces, or the same class centred within object_match_distance) is
  // kept once, its evidence combined.
  const size_t formed = rebuilt.size();
  for (size_t k = 0; k < map->objects.size(); ++k) {
    if (heir[k] >= 0) continue;
    const MapObject& old = map->objects[k];
    auto same = std::find_if(rebuilt.begin() + formed, rebuilt.end(), [&](const MapObject& o) {
      int shared = 0;
      for (int f : old.landmarks) shared += std::count(o.landmarks.begin(), o.landmarks.end(), f) > 0;
      return shared >= 2 || (o.label == old.label && (o.center - old.center).norm() < object_match_distance);
    });
    if (same == rebuilt.end()) {
      rebuilt.push_back(old);
      rebuilt.back().id = static_cast<int>(rebuilt.size()) - 1;
      continue;
    }
    Fold(old, *map, &*same);
  }
  map->objects = std::move(rebuilt);
}

std::vector<Eigen::Vector3d> MapCorners(const PlaneMap& map, const PlaneGraphConfig& config) {
  Cloud cloud;
  FrameModel graph = MapGraph(map, config, &cloud);
  AggregateObjects(cloud, config, &graph);
  std::vector<Eigen::Vector3d> corners;
  for (const TrihedralAngle& angle : graph.angles) corners.push_back(angle.corner);
  return corners;
}

MapMergeResult MergeMaps(const PlaneMap& target, const PlaneMap& source, const Pose3& T_guess,
                         const MapMergeConfig& config, const ObjectModel& model) {
  ValidateConfig(config, "merge.");
  MapMergeResult result;
  result.map = target;
  result.T_target_source = T_guess;
  if (target.landmarks.empty() || source.landmarks.empty()) {
    result.reason = "a map without planes";
    return result;
  }
  // 1. Candidate pairs within the gates around the guess, best first per source landmark.
  std::vector<PlaneCorrespondence> correspondences;
  const double max_angle = config.search_angle_deg * kDegToRad;
  double max_weight = 0.0;
  for (const PlaneLandmark& s : source.landmarks) {
    const Plane placed = TransformPlane(T_guess, s.plane);
    const Eigen::Vector3d centroid = Centroid(s);
    const Eigen::Vector3d placed_centroid = T_guess * centroid;
    const Box3 box = TransformBox(T_guess, s.low, s.high);  // the source extent placed by the guess
    std::vector<std::pair<double, int>> mine;
    for (const PlaneLandmark& t : target.landmarks) {
      const double angle = NormalAngle(placed, t.plane);
      const double distance = std::abs(t.plane.SignedDistance(placed_centroid));
      if (angle > max_angle || distance > config.search_distance) continue;
      if (!t.Overlaps(box.low, box.high, config.overlap_margin)) continue;
      mine.emplace_back(angle / max_angle + distance / config.search_distance, t.id);
    }
    std::sort(mine.begin(), mine.end());
    if (static_cast<int>(mine.size()) > config.max_candidates) mine.resize(config.max_candidates);
    for (const auto& [score, t] : mine) {
      // Weight: the surface's size, as the square root of the points it holds.
      const double weight = std::sqrt(static_cast<double>(std::max<size_t>(1, s.points.size())));
      max_weight = std::max(max_weight, weight);
      correspondences.push_back({s.plane, target.landmarks[t].plane, weight, centroid, s.id});
    }
  }
  for (PlaneCorrespondence& c : correspondences) c.weight /= max_weight;
  result.candidates = static_cast<int>(correspondences.size());

  // 2. The closed-form transform in RANSAC, the guess a hypothesis, poses far from it ruled out.
  const auto plausibility = [&](const Pose3& T) {
    const Pose3 correction = T_guess.inverse() * T;
    return correction.translation().norm() <= config.max_correction &&
                   RotationAngle(correction.linear()) <= config.max_correction_deg * kDegToRad
               ? 1.0
               : 0.0;
  };
  const PlaneRansacResult ransac = EstimatePoseRansac(correspondences, config.ransac, {T_guess}, plausibility);
  if (!ransac.ok) {
    result.reason = std::to_string(correspondences.size()) + " candidate plane pairs: " + ransac.reason;
    return result;
  }
  result.inliers = static_cast<int>(ransac.inliers.size());
  Pose3 T = ransac.T_target_source;

  // 3. ICP on the landmarks' points (each point with its plane's normal).
  const auto points = [](const PlaneMap& map) {
    pcl::PointCloud<pcl::PointNormal> cloud;
    for (const PlaneLandmark& l : map.landmarks) {
      for (const Eigen::Vector3f& p : l.points) {
        pcl::PointNormal q;
        q.getVector3fMap() = p;
        q.getNormalVector3fMap() = l.plane.normal.cast<float>();
        cloud.push_back(q);
      }
    }
    return cloud;
  };
  const pcl::PointCloud<pcl::PointNormal> source_points = points(source), target_points = points(target);
  if (!source_points.empty() && !target_points.empty()) {
    const IcpResult icp = RefineIcp(source_points, target_points, T, config.icp);
    if (icp.converged &&
        IsSmallCorrection(T.inverse() * icp.T_target_source, config.refine_max_translation, config.refine_max_rotation_deg)) {
      T = icp.T_target_source;
      result.refined = true;
    }
  }
  result.T_target_source = T;

  // 4. The source in the target's world, appended; one surface's landmarks fused, edges merged
  //    (the longest of each pair), keyframes kept; then the objects rebuilt from the graph.
  PlaneMap moved = source;
  TransformMap(T, &moved);
  PlaneMap& merged = result.map;
  const int offset = static_cast<int>(merged.landmarks.size());
  const int object_offset = static_cast<int>(merged.objects.size());
  for (PlaneLandmark l : moved.landmarks) {
    l.id += offset;
    merged.landmarks.push_back(std::move(l));
  }
  for (MapEdge e : moved.edges) {
    e.landmark_a += offset;
    e.landmark_b += offset;
    merged.edges.push_back(e);
  }
  for (MapObject o : moved.objects) {
    o.id += object_offset;
    for (int& f : o.landmarks) f += offset;
    for (auto& vote : o.grasp_votes) vote.first += offset;
    if (o.grasp_landmark >= 0) o.grasp_landmark += offset;
    if (o.x_landmark >= 0) o.x_landmark += offset;
    merged.objects.push_back(std::move(o));
  }
  merged.keyframes.insert(merged.keyframes.end(), moved.keyframes.begin(), moved.keyframes.end());
  result.fused = FuseDuplicateLandmarks(config, &merged);
  RebuildObjects(model, config.object_match_distance, &merged);
  result.ok = true;
  return result;
}

}  // namespace planemap
