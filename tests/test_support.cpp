#include "test_support.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

namespace fs = std::filesystem;

namespace planemap::testing {

std::string SourcePath(const std::string& relative) { return std::string(PLANEMAP_SOURCE_DIR) + "/" + relative; }
std::string SharedPath(const std::string& relative) {
  // ../shared beside the repository root, or wherever PLANEMAP_SHARED_DIR points.
  const char* override_dir = std::getenv("PLANEMAP_SHARED_DIR");
  return std::string(override_dir != nullptr ? override_dir : PLANEMAP_SHARED_DIR) + "/" + relative;
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

}  // namespace planemap::testing
