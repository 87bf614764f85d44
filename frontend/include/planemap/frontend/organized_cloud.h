#pragma once
// Step 1 of the frontend: depth + colour + intrinsics -> an organized, coloured point cloud.
#include <string>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "planemap/core/config.h"
#include "planemap/core/intrinsics.h"
#include "planemap/core/rgbd_frame.h"

namespace planemap {

using Cloud = pcl::PointCloud<pcl::PointXYZRGB>;

struct CloudConfig {
  double min_depth = 0.3;  // nearer readings are invalid [m]
  double max_depth = 6.0;  // farther readings are invalid [m] (Kinect-class noise exceeds 5 cm beyond)

  std::string CrossCheck() const {
    return min_depth < max_depth ? "" : "min_depth " + config_detail::ShortNumber(min_depth) + " must be below max_depth " + config_detail::ShortNumber(max_depth);
  }

  template <class V>
  void VisitFields(V&& v) {
    v("min_depth", min_depth, Check::kNonNegative);
    v("max_depth", max_depth, Check::kPositive);
  }
};

// One point per pixel (width x height, row-major, is_dense = false). A pixel without a usable
// depth (0, NaN, infinite, outside [min_depth, max_depth]) gets NaN coordinates: it is never a
// point at the origin. Throws std::invalid_argument if the images' size differs from the camera.
// With AVX2 where the processor has it (the build targets plain x86-64): the same cloud.
Cloud::Ptr MakeOrganizedCloud(const RgbdFrame& frame, const CameraIntrinsics& camera, const CloudConfig& config);

// MakeOrganizedCloud's two ways, for the test that holds them equal bit for bit: avx2 may be true
// only if OrganizedCloudHasAvx2().
bool OrganizedCloudHasAvx2();
Cloud::Ptr MakeOrganizedCloud(const RgbdFrame& frame, const CameraIntrinsics& camera, const CloudConfig& config,
                              bool avx2);

// True for a point with finite coordinates.
inline bool IsValidPoint(const pcl::PointXYZRGB& p) { return std::isfinite(p.z); }

}  // namespace planemap
