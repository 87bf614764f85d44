#include "planemap/core/intrinsics.h"

namespace planemap {

CameraIntrinsics CameraIntrinsics::Scaled(double factor) const {
  CameraIntrinsics scaled = *this;
  scaled.fx = fx * factor;
  scaled.fy = fy * factor;
  // Pixel centres sit at integer coordinates, so the image corner (-0.5, -0.5) is what scales.
  scaled.cx = (cx + 0.5) * factor - 0.5;
  scaled.cy = (cy + 0.5) * factor - 0.5;
  scaled.width = static_cast<int>(width * factor + 0.5);
  scaled.height = static_cast<int>(height * factor + 0.5);
  return scaled;
}

CameraIntrinsics LoadCameraIntrinsics(const std::string& file) {
  const YAML::Node root = LoadYamlFile(file);
  const CameraIntrinsics camera = LoadConfigNode<CameraIntrinsics>(root, file);  // values, types, unknown keys
  // A calibration is all of one camera's: a key left out would silently take another camera's
  // value (the TUM/OpenNI default) and every point would be off.
  std::string missing;
  for (const char* key : {"fx", "fy", "cx", "cy", "width", "height", "depth_scale"}) {
    if (!root.IsMap() || !root[key]) missing += std::string(missing.empty() ? "" : ", ") + key;
  }
  if (!missing.empty()) ThrowInputError(file, 0, "a camera file gives fx, fy, cx, cy, width, height and depth_scale; missing: " + missing);
  return camera;
}

}  // namespace planemap
