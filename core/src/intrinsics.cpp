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
  return LoadConfigFile<CameraIntrinsics>(file);
}

}  // namespace planemap
