#pragma once
// Steps 4-5 of the frontend: classify objects by graph patterns (paper Fig. 3, loaded from
// configs/patterns.yaml) and measure them: dimensions from their edges, centre by eq. (7), grasp
// sides and axis.
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/frame_model.h"
#include "planemap/frontend/organized_cloud.h"

namespace planemap {

struct PatternNode {
  std::string name;
  // floor | horizontal | vertical | any | support (the plane an object of two faces stands on:
  // the floor, a table, another object's top; FrameObject::support)
  std::string orientation = "any";
  template <class V>
  void VisitFields(V&& v) {
    v("name", name);
    v("orientation", orientation, OneOf{{"floor", "horizontal", "vertical", "any", "support"}});
  }
};

struct GraphPattern {
  std::string class_name;
  std::vector<PatternNode> nodes;
  std::vector<std::string> edges;  // "a-b": nodes a and b intersect
  double min_height = 0.0;         // object height above the floor [m], 0 = no limit
  double max_height = 0.0;         // [m], 0 = no limit
  std::string CrossCheck() const {
    return max_height == 0.0 || min_height <= max_height ? "" : "min_height must not exceed max_height";
  }

  template <class V>
  void VisitFields(V&& v) {
    v("class", class_name);
    v("nodes", nodes);
    v("edges", edges);
    v("min_height", min_height, Check::kNonNegative);
    v("max_height", max_height, Check::kNonNegative);
  }
};

struct PatternsConfig {
  std::vector<GraphPattern> patterns;
  template <class V>
  void VisitFields(V&& v) {
    v("patterns", patterns);
  }
};

// Loads and checks patterns (known orientations, edges between declared nodes); throws
// InputError naming the file and the pattern.
PatternsConfig LoadPatterns(const std::string& file);

struct ObjectConfig {
  double orientation_tolerance_deg = 15.0;  // horizontal / vertical within this of exact [deg]
  double axis_tolerance_deg = 15.0;         // an edge measures an axis if this close to it [deg]
  double max_up_tilt_deg = 45.0;            // no floor in view: an object face this close to the prior's up is its top [deg]
  double hand_span_min = 0.10;              // a two-handed grasp holds objects this wide ... [m]
  double hand_span_max = 0.40;              // ... up to this wide, across the held sides [m]
  double grasp_max_height = 0.60;           // and up to this tall [m]
  double edge_length_tolerance = 0.03;      // a complete edge this much shorter than a cut one along
                                            // the same axis is not the object's whole dimension [m]
  // Pieces of one edge: two of an object's edges on one axis that share a plane, the shorter
  // one's ends within edge_join_distance of the longer one's line, and at most edge_join_gap
  // apart along it, are one edge (a face the segmenter split in two meets the floor along two
  // pieces of one line); the dimension is their union's. edge_join_distance 0: off. [m], [m]
  double edge_join_distance = 0.01;
  double edge_join_gap = 0.02;

  // Objects of two faces (FrameObject::support): an axis no edge measures is measured on a face
  // that runs along it, from its plane's end of the box (a face across the axis, or the support)
  // to the far end of the face's points (face_extent_trim of them left out at either end: stray
  // points; 1% cuts the rendered box's faces about 1 cm short). That end is whole when the camera
  // sees past it: from each of the face's points within face_end_band of the end, in the 8
  // image directions within 60 deg of the end's, the first pixel with depth past the face's own
  // pixels and its plane's (the face as the cuboid has it: its normal along the object's axis
  // nearest to it, through its centroid), within face_end_search pixels, lies behind that plane
  // by face_end_gap or more, for at least face_end_free_share of those that see anything there
  // (what lies nearer, or the image's border, hides the face's continuation) and face_end_min_seen
  // of all (the rest may have no depth: a silhouette's shadow, a background out of range). Never
  // where the face runs more than face_end_max_pixel along the axis per pixel (its points'
  // gradient over the image: a face seen at a glancing angle places its end no finer than a
  // pixel's footprint). [fraction], [m], [px], [fraction], [m], [fraction], [m]
  double face_extent_trim = 0.002;
  double face_end_band = 0.01;
  int face_end_search = 8;
  double face_end_free_share = 0.7;
  double face_end_gap = 0.02;
  double face_end_min_seen = 0.25;
  double face_end_max_pixel = 0.01;

  std::string CrossCheck() const {
    return hand_span_min <= hand_span_max ? "" : "hand_span_min must not exceed hand_span_max";
  }

  template <class V>
  void VisitFields(V&& v) {
    v("orientation_tolerance_deg", orientation_tolerance_deg, Check::kPositive);
    v("axis_tolerance_deg", axis_tolerance_deg, Check::kPositive);
    v("max_up_tilt_deg", max_up_tilt_deg, Check::kPositive);
    v("hand_span_min", hand_span_min, Check::kNonNegative);
    v("hand_span_max", hand_span_max, Check::kPositive);
    v("grasp_max_height", grasp_max_height, Check::kPositive);
    v("edge_length_tolerance", edge_length_tolerance, Check::kNonNegative);
    v("edge_join_distance", edge_join_distance, Check::kNonNegative);
    v("edge_join_gap", edge_join_gap, Check::kNonNegative);
    v("face_extent_trim", face_extent_trim, Check::kProbability);
    v("face_end_band", face_end_band, Check::kPositive);
    v("face_end_search", face_end_search, Check::kPositive);
    v("face_end_free_share", face_end_free_share, Check::kProbability);
    v("face_end_gap", face_end_gap, Check::kPositive);
    v("face_end_min_seen", face_end_min_seen, Check::kProbability);
    v("face_end_max_pixel", face_end_max_pixel, Check::kPositive);
  }
};

// Height of an object's highest point above the floor (99th percentile of its faces' inliers),
// or its vertical extent when there is no floor [m].
double ObjectHeight(const Cloud& cloud, const FrameModel& model, const FrameObject& object, const Eigen::Vector3d& up);

// Sets each object's label: the class of the first matching pattern, else "unknown". Needs the
// objects measured first: a height limit only rules a class out when the height is known (the
// top is seen or the vertical edge is complete), not when the object runs out of the image.
void ClassifyObjects(const PatternsConfig& patterns, const ObjectConfig& config,
                     const Eigen::Vector3d& up, FrameModel* model);

// Sets each object's axes, dimensions, height, centre (eq. 7) and grasp sides and axis.
void MeasureObjects(const Cloud& cloud, const ObjectConfig& config, const Eigen::Vector3d& up, FrameModel* model);

}  // namespace planemap
