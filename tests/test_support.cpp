#include "test_support.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include <unistd.h>

namespace fs = std::filesystem;

namespace planemap::testing {

std::string SourcePath(const std::string& relative) { return std::string(PLANEMAP_SOURCE_DIR) + "/" + relative; }
std::string SharedPath(const std::string& relative) {
  // ../shared beside the repository root, or wherever PLANEMAP_SHARED_DIR points.
  const char* override_dir = std::getenv("PLANEMAP_SHARED_DIR");
  return std::string(override_dir != nullptr ? override_dir : PLANEMAP_SHARED_DIR) + "/" + relative;
}

std::string MissingShared(const std::string& relative) {
  const std::string path = SharedPath(relative);
  if (fs::exists(path)) return "";
  return path + " missing: the real data sets are in ../shared beside the repository (or set PLANEMAP_SHARED_DIR)";
}

bool SharedDataRequired() {
  const char* required = std::getenv("PLANEMAP_REQUIRE_SHARED_DATA");
  return required != nullptr && std::string(required) == "1";
}

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  path_ = (fs::temp_directory_path() /
           ("planemap_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++))).string();
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

std::string TempDir::Write(const std::string& name, const std::string& content) const {
  const std::string file = File(name);
  fs::create_directories(fs::path(file).parent_path());
  std::ofstream(file) << content;
  return file;
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

double RotationErrorDeg(const Pose3& a, const Pose3& b) {
  return RotationAngle(a.linear().transpose() * b.linear()) * 180.0 / M_PI;
}

double TranslationError(const Pose3& a, const Pose3& b) { return (a.translation() - b.translation()).norm(); }

::testing::AssertionResult PosesNear(const Pose3& a, const Pose3& b, double deg, double metres) {
  const double r = RotationErrorDeg(a, b), t = TranslationError(a, b);
  if (r <= deg && t <= metres) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "poses differ by " << r << " deg (max " << deg << ") and " << t
                                       << " m (max " << metres << ")";
}

::testing::AssertionResult PlanesNear(const Plane& a, const Plane& b, double deg, double metres) {
  const double angle = NormalAngle(a, b) * 180.0 / M_PI, offset = std::abs(a.offset - b.offset);
  if (angle <= deg && offset <= metres) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "planes differ by " << angle << " deg (max " << deg << ") and " << offset
                                       << " m in offset (max " << metres << ")";
}

// Where the synthetic room was seen from.
const Eigen::Vector3d kEye(0.0, 0.0, 0.5);

MapObject BoxObject(const Eigen::Vector3d& center, double yaw_deg, const Eigen::Vector3d& dimensions, double grasp_side) {
  MapObject box;
  box.label = "box";
  box.center = center;
  box.axes = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  box.dimensions = dimensions;
  box.has_grasp_axis = true;
  box.grasp_axis = grasp_side * box.axes.col(0);
  return box;
}

PlaneLandmark Rectangle(int id, const Eigen::Vector3d& centre, const Eigen::Vector3d& u, double half_u,
                        const Eigen::Vector3d& v, double half_v) {
  PlaneLandmark l;
  l.id = id;
  Eigen::Vector3d normal = u.cross(v).normalized();
  if (normal.dot(kEye - centre) < 0.0) normal = -normal;
  l.plane = Plane{normal, -normal.dot(centre)};
  std::set<long long> voxels;
  for (double a = -half_u; a <= half_u + 1e-9; a += 0.02) {
    for (double b = -half_v; b <= half_v + 1e-9; b += 0.02) {
      const Eigen::Vector3d p = centre + a * u + b * v;
      l.moments.Add(p);
      l.low = l.low.cwiseMin(p);
      l.high = l.high.cwiseMax(p);
      if (voxels.insert(VoxelKey(p.cast<float>(), 0.05)).second) l.points.push_back(p.cast<float>());
    }
  }
  l.observations = 1;
  return l;
}

MapEdge RoomEdge(int a, int b, const Eigen::Vector3d& start, const Eigen::Vector3d& end, bool complete, bool convex) {
  MapEdge e{std::min(a, b), std::max(a, b), start, end, (end - start).norm(), complete, 1};
  ++(convex ? e.convex_views : e.concave_views);
  return e;
}

PlaneMap SyntheticRoom() {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  PlaneMap map;
  map.landmarks = {Rectangle(kFloor, {1.0, 0.0, 0.0}, x, 2.0, y, 2.0),
                   Rectangle(kWallX, {3.0, 0.0, 1.2}, z, 1.2, y, 2.0),
                   Rectangle(kWallY, {1.0, 2.0, 1.2}, x, 2.0, z, 1.2),
                   Rectangle(kBoxX, {1.35, 0.3, 0.15}, z, 0.15, y, 0.2),
                   Rectangle(kBoxY, {1.5, 0.1, 0.15}, x, 0.15, z, 0.15),
                   Rectangle(kBoxTop, {1.5, 0.3, 0.3}, x, 0.15, y, 0.2)};
  map.landmarks[kFloor].floor_votes = 1;
  const Eigen::Vector3d corner(1.35, 0.1, 0.0);
  map.edges = {RoomEdge(kBoxX, kBoxTop, corner + 0.3 * z, corner + 0.3 * z + 0.4 * y, true, true),
               RoomEdge(kBoxY, kBoxTop, corner + 0.3 * z, corner + 0.3 * z + 0.3 * x, true, true),
               RoomEdge(kBoxX, kBoxY, corner, corner + 0.3 * z, true, true),
               RoomEdge(kFloor, kBoxX, corner, corner + 0.4 * y, true, false),
               RoomEdge(kFloor, kBoxY, corner, corner + 0.3 * x, true, false),
               RoomEdge(kFloor, kWallX, {3.0, -2.0, 0.0}, {3.0, 2.0, 0.0}, false, false),
               RoomEdge(kFloor, kWallY, {-1.0, 2.0, 0.0}, {3.0, 2.0, 0.0}, false, false),
               RoomEdge(kWallX, kWallY, {3.0, 2.0, 0.0}, {3.0, 2.0, 2.4}, false, false)};
  map.keyframes.push_back({0, 0.0, MakePoseRpy(-M_PI / 2, 0.0, -M_PI / 2, kEye)});  // looking along +x
  return map;
}

}  // namespace planemap::testing
