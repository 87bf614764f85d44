#pragma once
// A FrameModel out to files a person can look at: JSON (objects, planes, edges, corners), a PLY
// of planes, edges, corners, centres and grasp axes, and an overlay PNG of the planes (Fig. 6b).
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planemap/core/frame_model.h"
#include "planemap/core/image.h"
#include "planemap/core/intrinsics.h"
#include "planemap/core/plane_map.h"
#include "planemap/io/plane_map_io.h"

namespace planemap {

// The model as JSON text (inlier lists as counts). Units: metres, degrees where named _deg.
std::string FrameModelJson(const FrameModel& model, int indent = 2);

// `points`: the frame's point per pixel (NaN where none), camera frame.
void WriteFrameModelPly(const std::string& file, const FrameModel& model, const std::vector<Eigen::Vector3f>& points);

// Colour image with each plane's inliers tinted, edges, corners, centres and grasp axes drawn.
// A map as PLY: each landmark's voxel points, edges, object centres and axes, keyframes.
void WritePlaneMapPly(const std::string& file, const PlaneMap& map);

void WriteOverlayPng(const std::string& file, const ColorImage& color, const FrameModel& model,
                     const CameraIntrinsics& camera);

}  // namespace planemap
