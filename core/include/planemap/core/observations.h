#pragma once
// What tracking measured in each frame, kept for the back end: the planes it matched to landmarks
// (camera frame, with their fit covariances), the objects it matched to map objects, and the pose
// it estimated. The map holds the merged result; these hold the evidence behind it, so a batch
// or sliding-window problem can weigh every observation again (DESIGN.md, "The back end model").
#include <array>
#include <vector>

#include <Eigen/Core>

#include "planemap/core/plane.h"
#include "planemap/core/pose.h"

namespace planemap {

struct PlaneObservation {
  int landmark = -1;  // index into PlaneMap::landmarks
  Plane plane;        // camera frame, normal toward the camera
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();  // of (n, d), as DetectedPlane::covariance
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();   // of the inliers, camera frame [m]
  int inliers = 0;
};

// A frame object matched to a map object, in the camera frame (as FrameObject).
struct ObjectObservation {
  int object = -1;  // index into PlaneMap::objects
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();     // columns x, y, z
  Eigen::Vector3d dimensions = Eigen::Vector3d::Zero();   // longest edge along each axis [m]
  std::array<bool, 3> dimension_complete{};              // that edge is whole, else a lower bound
  Eigen::Vector3d center = Eigen::Vector3d::Zero();       // eq. (7) [m]
};

struct FrameObservations {
  int frame = 0;
  double stamp = 0.0;                        // [s]
  Pose3 T_world_camera = Pose3::Identity();  // tracking's pose
  bool degraded = false;                     // planes fixed only part of the pose
  bool lost = false;                         // the pose is the motion model's; nothing was observed
  std::vector<PlaneObservation> planes;
  std::vector<ObjectObservation> objects;
};

}  // namespace planemap
