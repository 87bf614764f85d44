#pragma once
// Pinhole intrinsics of a registered RGB-D camera (depth pixel = colour pixel).
#include <string>

#include <Eigen/Core>

#include "planemap/core/config.h"

namespace planemap {

struct CameraIntrinsics {
  double fx = 525.0;            // focal length along x [px]
  double fy = 525.0;            // focal length along y [px]
  double cx = 319.5;            // principal point x [px]
  double cy = 239.5;            // principal point y [px]
  int width = 640;              // image width [px]
  int height = 480;             // image height [px]
  double depth_scale = 5000.0;  // depth PNG units per metre (5000 TUM/ICL, 1000 millimetre sensors)

  template <class V>
  void VisitFields(V&& v) {
    v("fx", fx, Check::kPositive);
    v("fy", fy, Check::kPositive);
    v("cx", cx, Check::kNonNegative);
    v("cy", cy, Check::kNonNegative);
    v("width", width, Check::kPositive);
    v("height", height, Check::kPositive);
    v("depth_scale", depth_scale, Check::kPositive);
  }

  // Ray direction through pixel (u, v) with z = 1, so a point at depth z is z * Ray(u, v).
  // Pixel centres are at integer coordinates (OpenCV / TUM convention).
  Eigen::Vector3d Ray(double u, double v) const {
    return {(u - cx) / fx, (v - cy) / fy, 1.0};
  }

  // Pixel of a point in the camera optical frame (z > 0 assumed).
  Eigen::Vector2d Project(const Eigen::Vector3d& p_camera) const {
    return {fx * p_camera.x() / p_camera.z() + cx, fy * p_camera.y() / p_camera.z() + cy};
  }

  // The same camera with its image scaled by `factor` (e.g. 0.5 for 320x240).
  CameraIntrinsics Scaled(double factor) const;
};

// Loads and validates a camera file (configs/cameras/*.yaml).
CameraIntrinsics LoadCameraIntrinsics(const std::string& file);

}  // namespace planemap
