#pragma once
// Detected planes against ground truth: per labelled surface, the detected plane that overlaps it
// most (intersection over union of pixels), and its normal and offset errors.
#include <cstdint>
#include <map>
#include <vector>

#include "planemap/core/detected_plane.h"
#include "planemap/core/image.h"

namespace planemap {

struct PlaneMatch {
  std::uint16_t label = 0;
  int gt_pixels = 0;         // labelled pixels with a valid point
  int plane = -1;            // index of the matched detected plane, -1 if none
  double iou = 0.0;
  double normal_error_deg = 0.0;
  double offset_error = 0.0;  // [m]
};

struct PlaneEvaluation {
  std::vector<PlaneMatch> surfaces;  // one per evaluated surface, by label
  int matched = 0;
  double Recall() const { return surfaces.empty() ? 0.0 : static_cast<double>(matched) / surfaces.size(); }
};

// `planes_camera`: the true plane of every label in the camera frame (either orientation).
// `valid`: pixels that carry a point. Surfaces with fewer than `min_pixels` valid labelled pixels
// are not evaluated; a surface is matched when its best plane reaches `min_iou`.
PlaneEvaluation EvaluatePlanes(const std::vector<DetectedPlane>& planes, const LabelImage& labels,
                               const std::vector<bool>& valid, const std::map<std::uint16_t, Plane>& planes_camera,
                               int min_pixels = 1000, double min_iou = 0.5);

}  // namespace planemap
