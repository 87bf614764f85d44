#pragma once
// Shared helpers of the test suite: paths, temporary folders, pose and plane matchers.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "planemap/core/plane.h"
#include "planemap/core/plane_map.h"
#include "planemap/core/pose.h"

namespace planemap::testing {

// A path inside the source tree, e.g. SourcePath("configs/scenes/default.yaml").
std::string SourcePath(const std::string& relative);
// A path inside ../shared (the real data sets), e.g. SharedPath("data/tum_frame_pairs");
// the environment variable PLANEMAP_SHARED_DIR overrides where shared/ is.
std::string SharedPath(const std::string& relative);

// The real data sets are not in the repository: a clone alone has no ../shared. A test that reads
// them starts with PLANEMAP_REQUIRE_SHARED("data/..."): when that file or folder is missing the
// test is skipped with a message naming it, or fails with the same message when the environment
// sets PLANEMAP_REQUIRE_SHARED_DATA=1 (CI does: a run there cannot pass by skipping).
// MissingShared: "" when SharedPath(relative) exists, else that message.
std::string MissingShared(const std::string& relative);
bool SharedDataRequired();
#define PLANEMAP_REQUIRE_SHARED(relative)                                                      \
  do {                                                                                          \
    const std::string planemap_missing_ = ::planemap::testing::MissingShared(relative);         \
    if (!planemap_missing_.empty()) {                                                           \
      if (::planemap::testing::SharedDataRequired()) FAIL() << planemap_missing_;               \
      GTEST_SKIP() << planemap_missing_;                                                        \
    }                                                                                           \
  } while (false)

// A fresh, empty folder under the system temp dir, removed when the object dies.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string File(const std::string& name) const { return path_ + "/" + name; }
  // Writes `content` to File(name) and returns its path.
  std::string Write(const std::string& name, const std::string& content) const;

 private:
  std::string path_;
};

// Median of a sample (the upper one of an even count); 0 for an empty sample.
double Median(std::vector<double> values);

// Rotation error [deg] and translation error [m] between two poses.
double RotationErrorDeg(const Pose3& a, const Pose3& b);
double TranslationError(const Pose3& a, const Pose3& b);

// Asserts that two poses agree within `deg` degrees and `metres`.
::testing::AssertionResult PosesNear(const Pose3& a, const Pose3& b, double deg, double metres);

// Asserts that two planes agree within `deg` degrees between normals and `metres` in offset.
::testing::AssertionResult PlanesNear(const Plane& a, const Plane& b, double deg, double metres);

// Runs `fn` and asserts that it throws an exception of type `Exception` (any std::exception by
// default) whose message contains every fragment.
template <typename Exception = std::exception, typename Fn>
::testing::AssertionResult ThrowsWith(Fn&& fn, std::initializer_list<std::string> fragments) {
  try {
    fn();
  } catch (const std::exception& e) {
    const std::string message = e.what();
    if (dynamic_cast<const Exception*>(&e) == nullptr) {
      return ::testing::AssertionFailure() << "an exception of another type: '" << message << "'";
    }
    for (const std::string& f : fragments) {
      if (message.find(f) == std::string::npos) {
        return ::testing::AssertionFailure() << "message '" << message << "' lacks '" << f << "'";
      }
    }
    return ::testing::AssertionSuccess() << message;
  }
  return ::testing::AssertionFailure() << "no exception";
}

// A synthetic plane map: a room corner (floor, two walls) and a 0.3 x 0.4 x 0.3 m box centred at
// (1.5, 0.3, 0.15), seen from a camera 50 cm above the origin looking along +x: the box's -x and
// -y faces and its top, with their real intersections. World z up; normals face the camera.
enum RoomPlane { kFloor, kWallX, kWallY, kBoxX, kBoxY, kBoxTop };
PlaneMap SyntheticRoom();
// A landmark on the rectangle centre +- half_u * u +- half_v * v (normal toward that camera),
// sampled every 2 cm, its points kept one per 5 cm voxel.
PlaneLandmark Rectangle(int id, const Eigen::Vector3d& centre, const Eigen::Vector3d& u, double half_u,
                        const Eigen::Vector3d& v, double half_v);
// A map box centred at `center`, turned yaw_deg about the vertical, grasped from its +x face
// (grasp_side +1) or its -x face (-1).
MapObject BoxObject(const Eigen::Vector3d& center, double yaw_deg, const Eigen::Vector3d& dimensions, double grasp_side);
// An edge of such a map, seen once.
MapEdge RoomEdge(int a, int b, const Eigen::Vector3d& start, const Eigen::Vector3d& end, bool complete, bool convex);

}  // namespace planemap::testing
