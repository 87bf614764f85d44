#include "planemap/frontend/pcd_source.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include <pcl/io/pcd_io.h>

#include "planemap/core/error.h"

namespace planemap {

PcdFrame LoadOrganizedPcd(const std::string& file, const CameraIntrinsics& camera) {
  if (!std::filesystem::is_regular_file(file)) ThrowInputError(file, 0, "no such PCD file");
  // The header first: PCL's reader crashes on a file whose header holds no points (PCL 1.13).
  pcl::PCDReader reader;
  pcl::PCLPointCloud2 header;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version = 0, data_type = 0;
  unsigned int data_start = 0;
  // PCL throws std::exceptions of its own on some broken headers (a FIELDS line longer than COUNT's:
  // std::out_of_range); they name no file.
  int header_status = 0;
  try {
    header_status = reader.readHeader(file, header, origin, orientation, version, data_type, data_start);
  } catch (const std::exception& e) {
    ThrowInputError(file, 0, std::string("not a PCD file (broken header: ") + e.what() + ")");
  }
  if (header_status != 0) ThrowInputError(file, 0, "not a PCD file (no valid header)");
  if (header.width == 0 || header.height == 0) ThrowInputError(file, 0, "not a PCD file, or one without points");
  if (static_cast<int>(header.width) != camera.width || static_cast<int>(header.height) != camera.height) {
    ThrowInputError(file, 0, "cloud is " + std::to_string(header.width) + "x" + std::to_string(header.height) +
                                 " but the camera is " + std::to_string(camera.width) + "x" +
                                 std::to_string(camera.height) + " (an organized cloud is needed)");
  }
  for (const char* name : {"x", "y", "z"}) {
    if (std::none_of(header.fields.begin(), header.fields.end(), [&](const pcl::PCLPointField& f) { return f.name == name; })) {
      ThrowInputError(file, 0, std::string("cloud has no '") + name + "' field");
    }
  }
  pcl::PointCloud<pcl::PointXYZRGBL> raw;
  if (pcl::io::loadPCDFile(file, raw) != 0 || raw.width != header.width || raw.height != header.height) {
    ThrowInputError(file, 0, "cannot read the PCD file's points (truncated or corrupt)");
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
