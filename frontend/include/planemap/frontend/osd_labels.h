#pragma once
// The labelled surfaces of an OSD / mOSD scene: the table and each box's faces, read from the
// per-point labels (1-9 the table, 20-29 object 1, 30-39 object 2, ...: the data set's README).
// A label marks an object, not a face, so the faces are planes found through each object's
// points. test_real_frames judges the frontend's boxes against them; bench_frontend the
// segmenters' planes (EvaluatePlanes).
#include <cstdint>
#include <map>
#include <vector>

#include "planemap/core/frame_model.h"
#include "planemap/core/image.h"
#include "planemap/core/plane.h"
#include "planemap/frontend/organized_cloud.h"

namespace planemap {

// The object a label belongs to (1, 2, ...), 0 for the table and the background.
inline int OsdObjectOf(std::uint32_t label) { return label >= 20 ? static_cast<int>(label / 10) - 1 : 0; }
inline bool IsOsdTable(std::uint32_t label) { return label >= 1 && label <= 9; }

// A labelled face: its plane (normal toward the camera) and its pixels (v * width + u, ascending).
struct LabelledFace {
  Plane plane;
  std::vector<int> points;
};

// Planes through the points at `indices` (valid, ascending) by PCL's RANSAC (fixed seed), one
// after another, at most `max_planes`, each of at least 400 points (the segmenters' smallest
// plane) within 5 mm; each kept to its largest 4-connected piece in the image and refitted.
std::vector<LabelledFace> SacPlanes(const Cloud& cloud, const std::vector<int>& indices, int max_planes);

// Each labelled object's faces (at most four): SacPlanes through its valid points, by object.
std::map<int, std::vector<LabelledFace>> LabelledFaces(const Cloud& cloud,
                                                       const std::vector<std::uint32_t>& labels);

// The table's face: one SacPlanes plane through its valid points; none when it has no such plane.
std::vector<LabelledFace> LabelledTable(const Cloud& cloud, const std::vector<std::uint32_t>& labels);

// The table and the faces as EvaluatePlanes takes them: surface 1 the table, then each object's
// faces (2, 3, ...), each face's pixels labelled with its surface and its plane by surface.
struct LabelledSurfaces {
  LabelImage labels;                             // 0 = no labelled face
  std::map<std::uint16_t, Plane> planes_camera;  // by surface
};
LabelledSurfaces OsdSurfaces(const Cloud& cloud, const std::vector<std::uint32_t>& labels);

// How many faces a labelled box shows, read from its labelled faces alone (not from what the
// frontend found): 3 for a top (within 15 deg of horizontal, `up` the table's normal) and two
// sides (within 15 deg of vertical, 60 deg or more apart); else 2 when two of its faces are
// 60 deg or more apart; else 1.
int OsdFacesShown(const std::vector<LabelledFace>& faces, const Eigen::Vector3d& up);

// The labelled size of a box along `axis`: the extent of its points (`points`: indices into the
// cloud) from the 1st to the 99th percentile, so that single stray points do not count; for a box
// standing on the table (its points reach within 2 cm of `table`) and an axis within 10 deg of the
// table's normal, the height of its top (99th percentile) above the table, since the labels of a
// box's sides may stop short of the table [m].
double OsdLabelledExtent(const Cloud& cloud, const std::vector<int>& points, const Eigen::Vector3d& axis,
                         const Plane& table);

// The frontend's box objects (label "box") scored against an OSD scene's labelled boxes. A box is
// found by a box object whose centre lies in its labelled points' bounding box (camera frame)
// grown by 3 cm, and whose cuboid (centre, axes, dimensions) grown by 2 cm holds half of those
// points or more; each complete dimension of the best such object (the one holding most) is
// compared with OsdLabelledExtent. A false box is a box object whose centre lies in no labelled
// box's grown bounding box.
struct OsdBoxResult {
  int box = 0;          // the object's label number (OsdObjectOf)
  int faces_shown = 0;  // OsdFacesShown
  int object = -1;      // index into the model's objects of the box object that finds it, -1: none
  double held = 0.0;    // the share of its labelled points that object's grown cuboid holds
  std::vector<double> dimension_error;  // |complete dimension - labelled extent| [m]
};
struct OsdBoxScore {
  std::vector<OsdBoxResult> boxes;
  int box_objects = 0;
  int false_boxes = 0;
};
OsdBoxScore ScoreOsdBoxes(const Cloud& cloud, const std::vector<std::uint32_t>& labels, const FrameModel& model);

}  // namespace planemap
