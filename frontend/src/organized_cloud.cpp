#include "planemap/frontend/organized_cloud.h"

#include <limits>
#include <stdexcept>
#include <string>

namespace planemap {

Cloud::Ptr MakeOrganizedCloud(const RgbdFrame& frame, const CameraIntrinsics& camera, const CloudConfig& config) {
  const int w = camera.width, h = camera.height;
  if (frame.depth.width() != w || frame.depth.height() != h) {
    throw std::invalid_argument("frame " + std::to_string(frame.index) + ": depth is " +
                                std::to_string(frame.depth.width()) + "x" + std::to_string(frame.depth.height()) +
                                ", camera is " + std::to_string(w) + "x" + std::to_string(h));
  }
  const bool has_color = frame.color.width() == w && frame.color.height() == h;
  auto cloud = std::make_shared<Cloud>(w, h);
  cloud->is_dense = false;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float z_min = static_cast<float>(config.min_depth), z_max = static_cast<float>(config.max_depth);
  const double inv_fx = 1.0 / camera.fx, inv_fy = 1.0 / camera.fy;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      pcl::PointXYZRGB& p = (*cloud)(u, v);
      const float z = frame.depth.at(u, v);
      if (has_color) {
        const Rgb8& c = frame.color.at(u, v);
        p.r = c[0];
        p.g = c[1];
        p.b = c[2];
      }
      if (!(z >= z_min && z <= z_max)) {  // also false for NaN
        p.x = p.y = p.z = nan;
        continue;
      }
      p.x = static_cast<float>((u - camera.cx) * inv_fx * z);
      p.y = static_cast<float>((v - camera.cy) * inv_fy * z);
      p.z = z;
    }
  }
  return cloud;
}

}  // namespace planemap
