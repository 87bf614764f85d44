#include "planemap/core/object_eval.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace planemap {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// Angle [rad] between the lines of two vectors, in [0, pi/2].
double LineAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), std::abs(a.dot(b)));
}

// The truth's edge most parallel to each estimate axis: estimate minus truth length [m], by
// estimate axis and by true edge.
void MeasureDimensions(const ObjectEstimate& estimate, const ObjectTruth& truth, ObjectError* error) {
  const Eigen::Matrix3d R_world_object = truth.T_world_object.linear();
  for (int k = 0; k < 3; ++k) {
    if (!estimate.dimension_complete[k]) continue;
    Eigen::Index edge = 0;
    (R_world_object.transpose() * estimate.axes.col(k)).cwiseAbs().maxCoeff(&edge);
    error->dimension_error[k] = estimate.dimensions[k] - truth.dimensions[edge];
    error->true_edge_error[edge] = error->dimension_error[k];
  }
}

ObjectError Measure(const ObjectTruth& truth, const ObjectEstimate& estimate, int index) {
  ObjectError error;
  error.name = truth.name;
  error.type = truth.type;
  error.estimate = index;
  error.center_error = (estimate.center - truth.T_world_object.translation()).norm();
  MeasureDimensions(estimate, truth, &error);
  error.axis_error_deg = HorizontalAxisErrorDeg(estimate.axes.col(0), truth.T_world_object);
  if (estimate.grasp_axis) error.grasp_axis_error_deg = HorizontalAxisErrorDeg(*estimate.grasp_axis, truth.T_world_object);
  return error;
}

}  // namespace

double HorizontalAxisErrorDeg(const Eigen::Vector3d& axis, const Pose3& T_world_object) {
  const Eigen::Matrix3d R = T_world_object.linear();
  return std::min(LineAngle(axis, R.col(0)), LineAngle(axis, R.col(1))) * kRadToDeg;
}

std::string ExpectedClass(const std::string& type) { return type == "open_locker" ? "locker" : type; }

ObjectEstimate Transformed(const Pose3& T_new_old, const ObjectEstimate& object) {
  ObjectEstimate moved = object;
  moved.center = T_new_old * object.center;
  moved.axes = T_new_old.linear() * object.axes;
  if (object.grasp_axis) moved.grasp_axis = T_new_old.linear() * *object.grasp_axis;
  return moved;
}

std::vector<ObjectError> EvaluateObjects(const std::vector<ObjectTruth>& truths,
                                         const std::vector<ObjectEstimate>& estimates, const EvalConfig& config) {
  std::vector<ObjectError> errors;
  std::vector<size_t> evaluated;  // indices into truths
  for (size_t t = 0; t < truths.size(); ++t) {
    const auto& types = config.object_types;
    if (std::find(types.begin(), types.end(), truths[t].type) == types.end()) continue;
    evaluated.push_back(t);
    errors.push_back({});
    errors.back().name = truths[t].name;
    errors.back().type = truths[t].type;
  }
  // Nearest pairs first, each estimate and each truth used once.
  std::vector<std::tuple<double, size_t, size_t>> candidates;  // distance [m], errors index, estimate
  for (size_t k = 0; k < evaluated.size(); ++k) {
    const Eigen::Vector3d true_center = truths[evaluated[k]].T_world_object.translation();
    for (size_t e = 0; e < estimates.size(); ++e) {
      const double distance = (estimates[e].center - true_center).norm();
      if (distance <= config.max_object_distance) candidates.emplace_back(distance, k, e);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> estimate_used(estimates.size(), false);
  for (const auto& [distance, k, e] : candidates) {
    if (errors[k].found() || estimate_used[e]) continue;
    estimate_used[e] = true;
    errors[k] = Measure(truths[evaluated[k]], estimates[e], static_cast<int>(e));
  }
  return errors;
}

std::vector<ObjectEstimate> MapObjectEstimates(const PlaneMap& map) {
  std::vector<ObjectEstimate> estimates;
  for (const MapObject& o : map.objects) {
    if (o.structure) continue;  // no object: a wall's piece (MapObject::structure)
    ObjectEstimate e;
    e.id = o.id;
    e.label = o.label;
    e.dimensions = o.dimensions;
    e.dimension_complete = o.dimension_complete;
    e.center = o.center;
    e.axes = o.axes;
    if (o.has_grasp_axis) e.grasp_axis = o.grasp_axis;
    e.observations = o.observations;
    estimates.push_back(e);
  }
  return estimates;
}

}  // namespace planemap
