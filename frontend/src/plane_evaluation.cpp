#include "planemap/frontend/plane_evaluation.h"

#include <cmath>

namespace planemap {

PlaneEvaluation EvaluatePlanes(const std::vector<DetectedPlane>& planes, const LabelImage& labels,
                               const std::vector<bool>& valid, const std::map<std::uint16_t, Plane>& planes_camera,
                               int min_pixels, double min_iou) {
  // Pixel counts per label, and per (label, plane) overlap.
  std::map<std::uint16_t, int> label_pixels;
  for (size_t i = 0; i < labels.size(); ++i) {
    if (valid[i] && labels.pixels()[i] != 0) ++label_pixels[labels.pixels()[i]];
  }
  std::map<std::pair<std::uint16_t, int>, int> overlap;
  for (const DetectedPlane& p : planes) {
    for (int i : p.inliers) {
      const std::uint16_t label = labels.pixels()[i];
      if (label != 0) ++overlap[{label, p.id}];
    }
  }
  PlaneEvaluation evaluation;
  for (const auto& [label, count] : label_pixels) {
    if (count < min_pixels || planes_camera.count(label) == 0) continue;
    PlaneMatch match;
    match.label = label;
    match.gt_pixels = count;
    for (const DetectedPlane& p : planes) {
      const auto it = overlap.find({label, p.id});
      if (it == overlap.end()) continue;
      const double iou = static_cast<double>(it->second) / (count + p.inliers.size() - it->second);
      if (iou > match.iou) {
        match.iou = iou;
        match.plane = p.id;
      }
    }
    if (match.iou < min_iou) match.plane = -1;
    if (match.plane >= 0) {
      Plane truth = planes_camera.at(label);
      const Plane& found = planes[match.plane].plane;
      if (truth.normal.dot(found.normal) < 0.0) truth = truth.Flipped();
      match.normal_error_deg = NormalAngle(truth, found) * 180.0 / M_PI;
      match.offset_error = std::abs(truth.offset - found.offset);
      ++evaluation.matched;
    }
    evaluation.surfaces.push_back(match);
  }
  return evaluation;
}

}  // namespace planemap
