#include "planemap/frontend/pcd_source.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <pcl/io/pcd_io.h>

#include "planemap/core/error.h"

namespace planemap {

namespace {

// Bytes one point may take (the sum of SIZE x COUNT over its fields): the PCD files planemap reads
// hold a few numbers a point; PCL's header reader allocates width x height x this before it reads
// a point, so a header claiming more is refused first (fuzz_pcd: SIZE 44444444444444444444444444
// asked for 206 GB).
constexpr long long kMaxPointBytes = 1024;

// PCL's reader trusts the header: it allocates POINTS (or WIDTH x HEIGHT) x the point's bytes
// before it reads a point. So every header line up to DATA is checked here first: each SIZE is 1,
// 2, 4 or 8 (the PCD format's), each COUNT a positive number, a point takes at most kMaxPointBytes,
// and WIDTH, HEIGHT and POINTS are the camera's (an organized cloud).
void CheckPcdHeader(const std::string& file, const CameraIntrinsics& camera) {
  std::ifstream in(file, std::ios::binary);
  std::vector<long long> sizes, counts;
  std::vector<std::string> types, fields;
  const long long expected_points = static_cast<long long>(camera.width) * camera.height;
  std::string line;
  for (int number = 1; in.tellg() < (1 << 20) && std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "DATA") break;
    if (key == "FIELDS") {
      fields.clear();
      for (std::string word; words >> word;) fields.push_back(word);
      continue;
    }
    if (key == "TYPE") {
      types.clear();
      for (std::string word; words >> word;) types.push_back(word);
      continue;
    }
    if (key != "SIZE" && key != "COUNT" && key != "WIDTH" && key != "HEIGHT" && key != "POINTS") continue;
    for (std::string word; words >> word;) {
      long long value = 0;
      std::size_t used = 0;
      try {
        value = std::stoll(word, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != word.size()) ThrowInputError(file, number, "not a PCD file (" + key + " '" + word + "' is no number)");
      if (key == "SIZE") {
        if (value != 1 && value != 2 && value != 4 && value != 8)
          ThrowInputError(file, number, "not a PCD file (SIZE " + word + " is no field size: 1, 2, 4 or 8)");
        sizes.push_back(value);
      } else if (key == "COUNT") {
        if (value < 1 || value > kMaxPointBytes) ThrowInputError(file, number, "not a PCD file (COUNT " + word + ")");
        counts.push_back(value);
      } else {
        const long long want = key == "WIDTH" ? camera.width : key == "HEIGHT" ? camera.height : expected_points;
        if (value != want) {
          ThrowInputError(file, number, key + " " + word + " but the camera's is " + std::to_string(want) +
                                            " (an organized cloud of the camera's " + std::to_string(camera.width) +
                                            "x" + std::to_string(camera.height) + " is needed)");
        }
        break;  // one number; what follows is no concern of the size
      }
    }
  }
  // Each field's TYPE and SIZE agree as the format has them (F: 4 or 8 bytes; I and U: 1, 2, 4 or
  // 8): PCL writes a value of the type's width into the field's SIZE bytes, past the point's end
  // for a 2-byte F (a heap corruption fuzz_pcd's sanitizers found later, in free).
  for (size_t k = 0; k < sizes.size() && k < types.size(); ++k) {
    const bool ok = types[k] == "F" ? sizes[k] == 4 || sizes[k] == 8 : types[k] == "I" || types[k] == "U";
    if (!ok) {
      ThrowInputError(file, 0, "not a PCD file (field " + std::to_string(k + 1) + " has TYPE " + types[k] + " and SIZE " +
                                   std::to_string(sizes[k]) + ")");
    }
  }
  // The fields planemap takes (pcl::PointXYZRGBL's) are copied 4 bytes each: PCL copies the
  // point type's width from the field, past the cloud's end when the field is narrower
  // (fuzz_pcd: heap-buffer-overflow in pcl::fromPCLPointCloud2).
  for (size_t k = 0; k < fields.size() && k < sizes.size(); ++k) {
    const std::string& f = fields[k];
    if (f != "x" && f != "y" && f != "z" && f != "rgb" && f != "rgba" && f != "label") continue;
    if (sizes[k] != 4 || (k < counts.size() && counts[k] != 1)) {
      ThrowInputError(file, 0, "not a cloud planemap reads (field '" + f + "' is not one 4-byte value: SIZE " +
                                   std::to_string(sizes[k]) + ")");
    }
  }
  long long bytes = 0;
  for (size_t k = 0; k < sizes.size(); ++k) bytes += sizes[k] * (k < counts.size() ? counts[k] : 1);
  if (bytes > kMaxPointBytes) {
    ThrowInputError(file, 0, "a point takes " + std::to_string(bytes) + " bytes (SIZE x COUNT), more than the " +
                                 std::to_string(kMaxPointBytes) + " of any cloud planemap reads");
  }
}

}  // namespace

PcdFrame LoadOrganizedPcd(const std::string& file, const CameraIntrinsics& camera) {
  if (!std::filesystem::is_regular_file(file)) ThrowInputError(file, 0, "no such PCD file");
  CheckPcdHeader(file, camera);
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
