#pragma once
// Merging plane/object maps (paper, "Merging plane object-based high-level map representation",
// Fig. 4): plane correspondences by normals and distances, the closed-form plane-to-plane
// transform inside RANSAC, refined by ICP on the landmarks' points; the maps aligned, landmarks
// that are one surface fused, the graphs merged with each edge the longest of the pair, then the
// objects re-aggregated from the merged graph and re-classified. The same fusion folds a map's
// own duplicate landmarks (one surface added twice while tracking) into one.
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/plane_map.h"
#include "planemap/core/pose.h"
#include "planemap/frontend/objects.h"
#include "planemap/frontend/plane_graph.h"
#include "planemap/frontend/plane_registration.h"

namespace planemap {

struct MapMergeConfig {
  // Candidate pairs, with the source placed by the initial guess: normals within search_angle_deg,
  // the source landmark's centroid within search_distance of the target's plane, extents that
  // overlap within overlap_margin; the best max_candidates per source landmark.
  double search_angle_deg = 15.0;   // [deg]
  double search_distance = 0.30;    // [m]
  int max_candidates = 3;
  double overlap_margin = 0.30;     // [m]
  // RANSAC's transform lies within this of the guess (parallel surfaces offer consistent false
  // matches farther away).
  double max_correction = 0.5;      // [m]
  double max_correction_deg = 20.0; // [deg]
  PlaneRansacConfig ransac = [] {
    PlaneRansacConfig c;
    c.max_iterations = 1000;
    return c;
  }();
  IcpConfig icp;
  double refine_max_translation = 0.05;  // an ICP correction moving more is refused [m]
  double refine_max_rotation_deg = 3.0;  // ... or turning more [deg]
  // Two landmarks are one surface (fused): normals within fuse_max_angle_deg, each centroid within
  // fuse_max_distance of the other's plane, extents overlapping within fuse_overlap_margin.
  double fuse_max_angle_deg = 3.0;    // [deg]
  double fuse_max_distance = 0.03;    // [m]
  double fuse_overlap_margin = 0.05;  // [m]
  double landmark_voxel = 0.05;       // a fused landmark keeps one point per voxel of this size [m]
  // A rebuilt object inherits the observations (complete edge lengths, centres, votes) of the
  // old objects it shares two faces with or whose centre lies this close.
  double object_match_distance = 0.25;  // [m]
  // Two map objects are one (fused) when their cuboids share this much of the smaller one
  // (CuboidOverlap): the same box mapped twice, from views that did not match it to the first.
  double fuse_object_overlap = 0.5;     // [0, 1]

  template <class V>
  void VisitFields(V&& v) {
    v("search_angle_deg", search_angle_deg, Check::kPositive);
    v("search_distance", search_distance, Check::kPositive);
    v("max_candidates", max_candidates, Check::kPositive);
    v("overlap_margin", overlap_margin, Check::kNonNegative);
    v("max_correction", max_correction, Check::kPositive);
    v("max_correction_deg", max_correction_deg, Check::kPositive);
    v("ransac", ransac);
    v("icp", icp);
    v("refine_max_translation", refine_max_translation, Check::kPositive);
    v("refine_max_rotation_deg", refine_max_rotation_deg, Check::kPositive);
    v("fuse_max_angle_deg", fuse_max_angle_deg, Check::kPositive);
    v("fuse_max_distance", fuse_max_distance, Check::kPositive);
    v("fuse_overlap_margin", fuse_overlap_margin, Check::kNonNegative);
    v("landmark_voxel", landmark_voxel, Check::kPositive);
    v("object_match_distance", object_match_distance, Check::kPositive);
    v("fuse_object_overlap", fuse_object_overlap, Check::kPositive);
  }
};

// What objects are made of and how they are classified: the frontend's graph and object
// settings and the graph patterns.
struct ObjectModel {
  PlaneGraphConfig graph;
  ObjectConfig objects;
  PatternsConfig patterns;
};

struct MapMergeResult {
  PlaneMap map;                               // in the target's world frame
  Pose3 T_target_source = Pose3::Identity();  // the source's world in the target's
  bool ok = false;                            // aligned and merged; else `map` is the target as it was
  bool refined = false;                       // the ICP refinement was accepted
  int candidates = 0;                         // candidate landmark pairs
  int inliers = 0;                            // RANSAC's inlier pairs
  int fused = 0;                              // landmarks folded into another
  std::string reason;                         // why not ok
};

// Merges `source` into `target`. `T_guess` is the source world's pose in the target's as far as
// it is known (identity: two runs started from the same pose, or anchored to one ground truth).
// Throws std::invalid_argument for a bad config.
MapMergeResult MergeMaps(const PlaneMap& target, const PlaneMap& source, const Pose3& T_guess,
                         const MapMergeConfig& config, const ObjectModel& model);

// Folds landmarks that are one surface (config's fuse_* gates) into one: moments and points
// united and the plane refit, edges merged (the longest of each pair), objects' faces and votes
// renumbered. Landmark ids are renumbered densely. Returns the number of landmarks folded.
int FuseDuplicateLandmarks(const MapMergeConfig& config, PlaneMap* map);

// Folds map objects whose cuboids overlap by fuse_object_overlap or more into one: their views,
// faces and votes united, the dimensions, centre, class and grasp axis taken from them again.
// Objects that are room structure (MapObject::structure) are dropped. Object ids are renumbered
// densely. Returns the number of objects folded.
int FuseDuplicateObjects(const MapMergeConfig& config, PlaneMap* map);

// Re-aggregates the map's objects from its graph (trihedral angles of landmarks joined by map
// edges, aggregated angle by angle, paper Fig. 4) and re-classifies them by the patterns. Each
// rebuilt object keeps the observations of the old objects it matches (see
// MapMergeConfig::object_match_distance): a dimension seen whole is their mean, else the longest
// edge bounds it; old objects the graph no longer forms are kept as they were.
void RebuildObjects(const ObjectModel& model, double object_match_distance, PlaneMap* map);

// The trihedral corners of the map's graph (3-cycles of landmarks joined by map edges, as
// RebuildObjects finds them), world [m]: for display.
std::vector<Eigen::Vector3d> MapCorners(const PlaneMap& map, const PlaneGraphConfig& config);

}  // namespace planemap
