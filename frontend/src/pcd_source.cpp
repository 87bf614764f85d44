#include "planemap/frontend/pcd_source.h"

#include <cmath>
#include <filesystem>
#include <limits>

#include <pcl/io/pcd_io.h>

#include "planemap/core/error.h"

namespace planemap {

PcdFrame LoadOrganizedPcd(const std::string& file, const CameraIntrinsics& camera) {
  pcl::PointCloud<pcl::PointXYZRGBL> raw;
  if (!std::filesystem::exists(file) || pcl::io::loadPCDFile(file, raw) != 0) {
    ThrowInputError(file, 0, "cannot read PCD file");
  }
  if (static_cast<int>(raw.width) != camera.width || static_cast<int>(raw.height) != camera.height) {
    ThrowInputError(file, 0, "cloud is " + std::to_string(raw.width) + "x" + std::to_string(raw.height) +
                                 " but the camera is " + std::to_string(camera.width) + "x" +
                                 std::to_string(camera.height) + " (an organized cloud is needed)");
  }
  PcdFrame frame;
  frame.cloud = std::make_shared<Cloud>(raw.width, raw.height);
  frame.cloud->is_dense = false;
  frame.color = ColorImage(camera.width, camera.height);
  frame.labels.resize(raw.size());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (size_t i = 0; i < raw.size(); ++i) {
    const auto& p = raw[i];
    auto& q = (*frame.cloud)[i];
    const bool valid = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && p.z > 0;
    q.x = valid ? p.x : nan;
    q.y = valid ? p.y : nan;
    q.z = valid ? p.z : nan;
    q.r = p.r;
    q.g = p.g;
    q.b = p.b;
    frame.color.pixels()[i] = {p.r, p.g, p.b};
    frame.labels[i] = p.label;
  }
  return frame;
}

}  // namespace planemap
