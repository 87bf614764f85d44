#pragma once
// PNG reading and writing at the boundary (OpenCV imgcodecs). Errors name the file.
#include <cstddef>
#include <string>

#include "planemap/core/image.h"
#include "planemap/core/intrinsics.h"

namespace planemap {

// `context` (e.g. "depth.txt:12") is prepended to error messages to say who referred to the file.
ColorImage ReadColorPng(const std::string& file, const CameraIntrinsics& camera,
                        const std::string& context = "");
// Depth in metres from a 16-bit PNG of camera.depth_scale units per metre; 0 stays 0 (no data).
DepthImage ReadDepthPng(const std::string& file, const CameraIntrinsics& camera,
                        const std::string& context = "");
LabelImage ReadLabelPng(const std::string& file, const CameraIntrinsics& camera,
                        const std::string& context = "");

void WriteColorPng(const std::string& file, const ColorImage& color);
// Depth rounded to the nearest unit of 1/depth_scale m; depth that does not fit in 16 bits
// (beyond 65535 / depth_scale m) is written as 0, no data, rather than clamped to a wrong value.
void WriteDepthPng(const std::string& file, const DepthImage& depth, double depth_scale);

// Sets the valid depths past what WriteDepthPng's 16 bits hold (over 65535 units once rounded,
// which it writes as 0) to 0, as they will be read back; returns how many there were.
size_t ClearDepthBeyondPng(DepthImage* depth, double depth_scale);
void WriteLabelPng(const std::string& file, const LabelImage& labels);

}  // namespace planemap
