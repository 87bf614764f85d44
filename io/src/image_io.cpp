#include "planemap/io/image_io.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "planemap/core/error.h"

namespace planemap {
namespace {

std::string Where(const std::string& file, const std::string& context) {
  return context.empty() ? file : context + ": " + file;
}

cv::Mat ReadOrThrow(const std::string& file, const std::string& context) {
  const cv::Mat image = cv::imread(file, cv::IMREAD_UNCHANGED);
  if (image.empty()) ThrowInputError(Where(file, context), 0, "cannot read image (missing file or not an image)");
  return image;
}

void CheckSize(const cv::Mat& image, const CameraIntrinsics& camera, const std::string& where) {
  if (image.cols != camera.width || image.rows != camera.height) {
    ThrowInputError(where, 0,
                    "image is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                        " but the camera is " + std::to_string(camera.width) + "x" +
                        std::to_string(camera.height));
  }
}

void WriteOrThrow(const std::string& file, const cv::Mat& image) {
  bool ok = false;
  try {
    ok = cv::imwrite(file, image);
  } catch (const cv::Exception& e) {
    ThrowInputError(file, 0, std::string("cannot write image: ") + e.what());
  }
  if (!ok) ThrowInputError(file, 0, "cannot write image");
}

}  // namespace

ColorImage ReadColorPng(const std::string& file, const CameraIntrinsics& camera,
                        const std::string& context) {
  const std::string where = Where(file, context);
  cv::Mat image = ReadOrThrow(file, context);
  if (image.depth() != CV_8U) ThrowInputError(where, 0, "colour image must have 8 bits per channel");
  CheckSize(image, camera, where);
  cv::Mat rgb;
  switch (image.channels()) {
    case 1: cv::cvtColor(image, rgb, cv::COLOR_GRAY2RGB); break;
    case 3: cv::cvtColor(image, rgb, cv::COLOR_BGR2RGB); break;
    case 4: cv::cvtColor(image, rgb, cv::COLOR_BGRA2RGB); break;
    default: ThrowInputError(where, 0, "colour image has " + std::to_string(image.channels()) + " channels");
  }
  ColorImage color(rgb.cols, rgb.rows);
  for (int v = 0; v < rgb.rows; ++v) {
    const auto* row = rgb.ptr<cv::Vec3b>(v);
    for (int u = 0; u < rgb.cols; ++u) color.at(u, v) = {row[u][0], row[u][1], row[u][2]};
  }
  return color;
}

DepthImage ReadDepthPng(const std::string& file, const CameraIntrinsics& camera,
                        const std::string& context) {
  const std::string where = Where(file, context);
  const cv::Mat image = ReadOrThrow(file, context);
  if (image.type() == CV_8UC1 || image.depth() == CV_8U) {
    ThrowInputError(where, 0, "depth image has 8 bits per pixel; expected a 16-bit PNG of " +
                                  std::to_string(camera.depth_scale) + " units per metre");
  }
  if (image.type() != CV_16UC1) ThrowInputError(where, 0, "depth image must be a single-channel 16-bit PNG");
  CheckSize(image, camera, where);
  DepthImage depth(image.cols, image.rows);
  const float inv_scale = static_cast<float>(1.0 / camera.depth_scale);
  for (int v = 0; v < image.rows; ++v) {
    const auto* row = image.ptr<std::uint16_t>(v);
    for (int u = 0; u < image.cols; ++u) depth.at(u, v) = row[u] * inv_scale;  // 0 stays 0
  }
  return depth;
}

LabelImage ReadLabelPng(const std::string& file, const CameraIntrinsics& camera,
                        const std::string& context) {
  const std::string where = Where(file, context);
  const cv::Mat image = ReadOrThrow(file, context);
  if (image.type() != CV_16UC1) ThrowInputError(where, 0, "label image must be a single-channel 16-bit PNG");
  CheckSize(image, camera, where);
  LabelImage labels(image.cols, image.rows);
  for (int v = 0; v < image.rows; ++v) {
    const auto* row = image.ptr<std::uint16_t>(v);
    std::copy(row, row + image.cols, &labels.at(0, v));
  }
  return labels;
}

void WriteColorPng(const std::string& file, const ColorImage& color) {
  cv::Mat bgr(color.height(), color.width(), CV_8UC3);
  for (int v = 0; v < color.height(); ++v) {
    auto* row = bgr.ptr<cv::Vec3b>(v);
    for (int u = 0; u < color.width(); ++u) {
      const Rgb8& c = color.at(u, v);
      row[u] = cv::Vec3b(c[2], c[1], c[0]);
    }
  }
  WriteOrThrow(file, bgr);
}

namespace {
// A depth rounded to PNG units; 0 when invalid.
double RoundedUnits(float z, double depth_scale) { return IsValidDepth(z) ? std::round(z * depth_scale) : 0.0; }
// A depth in PNG units; 0 (no data) when invalid or past what 16 bits hold.
std::uint16_t DepthUnits(float z, double depth_scale) {
  const double units = RoundedUnits(z, depth_scale);
  return units <= 65535.0 ? static_cast<std::uint16_t>(units) : 0;
}
}  // namespace

void WriteDepthPng(const std::string& file, const DepthImage& depth, double depth_scale) {
  cv::Mat image(depth.height(), depth.width(), CV_16UC1);
  for (int v = 0; v < depth.height(); ++v) {
    auto* row = image.ptr<std::uint16_t>(v);
    for (int u = 0; u < depth.width(); ++u) row[u] = DepthUnits(depth.at(u, v), depth_scale);
  }
  WriteOrThrow(file, image);
}

size_t ClearDepthBeyondPng(DepthImage* depth, double depth_scale) {
  size_t cleared = 0;
  for (int v = 0; v < depth->height(); ++v) {
    for (int u = 0; u < depth->width(); ++u) {
      float& z = depth->at(u, v);
      if (RoundedUnits(z, depth_scale) > 65535.0) {  // not a depth under half a unit: that is near, not far
        z = 0.0f;
        ++cleared;
      }
    }
  }
  return cleared;
}

void WriteLabelPng(const std::string& file, const LabelImage& labels) {
  cv::Mat image(labels.height(), labels.width(), CV_16UC1);
  for (int v = 0; v < labels.height(); ++v) {
    std::copy(&labels.at(0, v), &labels.at(0, v) + labels.width(), image.ptr<std::uint16_t>(v));
  }
  WriteOrThrow(file, image);
}

}  // namespace planemap
