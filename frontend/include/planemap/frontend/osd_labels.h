#pragma once
// The labelled surfaces of an OSD / mOSD scene: the table and each box's faces, read from the
// per-point labels (1-9 the table, 20-29 object 1, 30-39 object 2, ...: the data set's README).
// A label marks an object, not a face, so the faces are planes found through each object's
// points. test_real_frames judges the frontend's boxes against them; bench_frontend the
// segmenters' planes (EvaluatePlanes).
#include <cstdint>
#include <map>
#include <vector>

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

}  // namespace planemap
