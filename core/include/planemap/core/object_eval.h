#pragma once
// Accuracy of mapped objects against a scene's ground truth: centre, dimensions, axes.
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planemap/core/plane_map.h"
#include "planemap/core/pose.h"
#include "planemap/core/trajectory_eval.h"

namespace planemap {

// An object of a map file (world frame).
struct ObjectEstimate {
  int id = -1;
  std::string label;                                    // class, e.g. "box"
  Eigen::Vector3d dimensions = Eigen::Vector3d::Zero();  // edge lengths along the axes [m]
  std::array<bool, 3> dimension_complete{};             // that edge was seen whole
  Eigen::Vector3d center = Eigen::Vector3d::Zero();      // [m]
  // Columns x, y, z: x the normal of the largest vertical face, z up.
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  std::optional<Eigen::Vector3d> grasp_axis;            // unit, when a grasp side was chosen
  int observations = 0;
};

// The objects of a map, as estimates.
std::vector<ObjectEstimate> MapObjectEstimates(const PlaneMap& map);

// An object of the scene's ground truth.
struct ObjectTruth {
  std::string name;
  std::string type;  // "box", "locker", ...
  Pose3 T_world_object = Pose3::Identity();              // centre; axes along the edges
  Eigen::Vector3d dimensions = Eigen::Vector3d::Ones();  // along object x, y, z [m]
};

// Errors of one ground-truth object; NaN where not measured.
struct ObjectError {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  std::string name;
  std::string type;
  int estimate = -1;  // index into the estimates; -1: not found
  double center_error = kNaN;  // [m]
  // Estimate minus truth along each estimate axis (the truth's most parallel edge); NaN where the
  // estimate's edge is incomplete [m].
  Eigen::Vector3d dimension_error = Eigen::Vector3d::Constant(kNaN);
  // The same by the true object's edges (x, y, z of its frame) [m].
  Eigen::Vector3d true_edge_error = Eigen::Vector3d::Constant(kNaN);
  double axis_error_deg = kNaN;        // estimate x vs the nearest true horizontal face normal [deg]
  double grasp_axis_error_deg = kNaN;  // the same for the grasp axis [deg]
  bool found() const { return estimate >= 0; }
};

// The class the frontend's patterns give a scene object type ("open_locker" is a "locker").
std::string ExpectedClass(const std::string& type);

// Moves an estimate by a rigid transform (e.g. the ATE alignment into the ground truth's world).
ObjectEstimate Transformed(const Pose3& T_new_old, const ObjectEstimate& object);

// Pairs each truth of a type in config.object_types with the nearest unused estimate centre within
// config.max_object_distance (nearest pairs first) and measures its errors. Order of `truths`.
std::vector<ObjectError> EvaluateObjects(const std::vector<ObjectTruth>& truths,
                                         const std::vector<ObjectEstimate>& estimates, const EvalConfig& config);

// Angle [deg] between the line of `axis` and the nearest of the true object's ±x, ±y axes.
double HorizontalAxisErrorDeg(const Eigen::Vector3d& axis, const Pose3& T_world_object);

}  // namespace planemap
