#pragma once
// The plane segmenters a user would pick instead of ours, as bench_frontend runs them: their
// planes as DetectedPlanes (id = position, inliers = pixel indices v * width + u).
#include <vector>

#include "planemap/core/detected_plane.h"
#include "planemap/core/image.h"
#include "planemap/core/intrinsics.h"
#include "planemap/frontend/organized_cloud.h"

namespace planemap {

// PCL's OrganizedMultiPlaneSegmentation with integral-image normals. Settings: the best recall of
// angular thresholds 2-10 deg, distance thresholds 2 and 5 cm and normal smoothing 10 and 20 tried
// on the rendered frames; planes of 400 points or more.
std::vector<DetectedPlane> PclOrganizedMultiPlanes(const Cloud::ConstPtr& cloud);

// OpenCV's rgbd::RgbdPlane (block-wise MSE growing) with its Kinect sensor error model, on the
// points cv::rgbd::depthTo3d makes of `depth` [m] through `camera`.
std::vector<DetectedPlane> OpenCvRgbdPlanes(const DepthImage& depth, const CameraIntrinsics& camera);

}  // namespace planemap
