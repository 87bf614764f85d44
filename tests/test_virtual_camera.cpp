// The virtual camera's exact render against analytic geometry: depth by ray-plane intersection,
// labels by an independent brute-force search over all scene rectangles, markers by OpenCV.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/aruco.hpp>

#include "planemap/core/intrinsics.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/virtual_camera.h"
#include "planemap/sim/walk.h"
#include "sim_views.h"
#include "test_support.h"

namespace planemap::sim {
namespace {

using planemap::testing::LookAt;
using planemap::testing::SourcePath;

constexpr double kDegToRad = M_PI / 180.0;

CameraIntrinsics Xtion() { return LoadCameraIntrinsics(SourcePath("configs/cameras/xtion_nao.yaml")); }

RenderConfig Exact() {
  RenderConfig config;
  config.add_noise = false;
  return config;
}

// Viewpoints: the start of the default walk, its end near the box, and orbits around the box at
// 1-3 m and several heights.
std::vector<Pose3> Viewpoints() {
  std::vector<Pose3> poses;
  const Trajectory walk = LoadTrajectory(SourcePath("configs/walks/default.yaml"));
  poses.push_back(walk.front().T_world_camera);
  poses.push_back(walk[walk.size() / 2].T_world_camera);
  poses.push_back(walk.back().T_world_camera);
  const Eigen::Vector3d box(2.1, 0.1, 0.125);
  for (double r : {1.0, 2.0, 3.0}) {
    for (double bearing_deg : {150.0, 190.0, 230.0}) {
      const double b = bearing_deg * kDegToRad;
      poses.push_back(LookAt(box + Eigen::Vector3d(r * std::cos(b), r * std::sin(b), 0.4 + 0.2 * r), box));
    }
  }
  return poses;
}

class ExactRender : public ::testing::TestWithParam<int> {
 protected:
  ExactRender()
      : scene_(LoadScene(SourcePath("configs/scenes/default.yaml"))),
        camera_(Xtion()),
        virtual_camera_(scene_, camera_, Exact()),
        T_world_camera_(Viewpoints()[GetParam()]),
        frame_(virtual_camera_.RenderExact(T_world_camera_)) {}

  // Nearest surface along the pixel's ray by testing every rectangle of the scene.
  std::uint16_t BruteForceLabel(int u, int v, double* depth) const {
    const Eigen::Vector3d origin = T_world_camera_.translation();
    const Eigen::Vector3d dir = T_world_camera_.linear() * camera_.Ray(u, v);
    std::uint16_t best_label = 0;
    *depth = std::numeric_limits<double>::infinity();
    for (const Surface& s : scene_.surfaces) {
      const std::optional<double> t = s.plane_world.IntersectRay(origin, dir);
      if (!t || *t >= *depth) continue;
      const Eigen::Vector3d local = origin + *t * dir - s.center_world;
      if (std::abs(local.dot(s.axis_u)) > s.half_u || std::abs(local.dot(s.axis_v)) > s.half_v) continue;
      *depth = *t;
      best_label = s.label;
    }
    return best_label;
  }

  Scene scene_;
  CameraIntrinsics camera_;
  VirtualCamera virtual_camera_;
  Pose3 T_world_camera_;
  RenderedFrame frame_;
};

TEST_P(ExactRender, DepthEqualsAnalyticRayPlaneDepth) {
  const Pose3 T_camera_world = T_world_camera_.inverse();
  double max_error = 0.0;
  size_t hits = 0;
  for (int v = 0; v < camera_.height; ++v) {
    for (int u = 0; u < camera_.width; ++u) {
      const std::uint16_t label = frame_.labels.at(u, v);
      if (label == 0) continue;
      ++hits;
      // The labelled plane, moved into the camera frame, intersected with the pixel's z = 1 ray.
      const Plane plane_c = TransformPlane(T_camera_world, scene_.surface(label).plane_world);
      const std::optional<double> z = plane_c.IntersectRay(Eigen::Vector3d::Zero(), camera_.Ray(u, v));
      ASSERT_TRUE(z.has_value());
      max_error = std::max(max_error, std::abs(*z - frame_.depth.at(u, v)));
    }
  }
  EXPECT_GT(hits, frame_.depth.size() / 2);  // the scene fills most of the view
  EXPECT_LT(max_error, 1e-6) << "metres";
}

TEST_P(ExactRender, LabelsMatchTheNearestSurfaceFoundByBruteForce) {
  std::mt19937 rng(1234 + GetParam());
  std::uniform_int_distribution<int> pick_u(0, camera_.width - 1), pick_v(0, camera_.height - 1);
  int compared = 0, agreed = 0;
  for (int k = 0; k < 2000; ++k) {
    const int u = pick_u(rng), v = pick_v(rng);
    double depth = 0.0;
    const std::uint16_t expected = BruteForceLabel(u, v, &depth);
    const std::uint16_t rendered = frame_.labels.at(u, v);
    // Pixels whose ray passes within 1e-9 m of an edge shared by two faces may go either way.
    if (expected != rendered && std::isfinite(depth) && std::abs(depth - frame_.depth.at(u, v)) < 1e-9) continue;
    ++compared;
    if (expected == rendered) ++agreed;
  }
  EXPECT_GT(compared, 1900);
  EXPECT_EQ(agreed, compared);
}

INSTANTIATE_TEST_SUITE_P(Viewpoints, ExactRender, ::testing::Range(0, static_cast<int>(Viewpoints().size())));

TEST(VirtualCamera, FrontoParallelWallAtKnownDistance) {
  const Scene scene = LoadScene(SourcePath("configs/scenes/default.yaml"));
  const CameraIntrinsics camera = Xtion();
  const VirtualCamera virtual_camera(scene, camera, Exact());
  // 2 m in front of the east wall (x = 4.5), looking at it square-on from 1.2 m height.
  const RenderedFrame frame = virtual_camera.RenderExact(LookAt({2.5, 2.0, 1.2}, {4.5, 2.0, 1.2}));
  const int cu = camera.width / 2, cv = camera.height / 2;
  EXPECT_NEAR(frame.depth.at(cu, cv), 2.0, 1e-6);
  EXPECT_EQ(scene.surface(frame.labels.at(cu, cv)).object, "wall_east");
}

TEST(VirtualCamera, BoxFaceDepthAndLabelSeenHeadOn) {
  const Scene scene = LoadScene(SourcePath("configs/scenes/default.yaml"));
  const CameraIntrinsics camera = Xtion();
  const VirtualCamera virtual_camera(scene, camera, Exact());
  const SceneObject& box = scene.object("box");
  const Eigen::Vector3d center = box.T_world_object.translation();
  const Eigen::Vector3d front = box.T_world_object.linear().col(0);  // +x face normal
  // 1.5 m from the box centre along its +x axis: the +x face is 1.5 - 0.125 m away.
  const RenderedFrame frame = virtual_camera.RenderExact(LookAt(center + 1.5 * front, center));
  const std::uint16_t label = frame.labels.at(camera.width / 2, camera.height / 2);
  ASSERT_NE(label, 0);
  EXPECT_EQ(scene.surface(label).object, "box");
  EXPECT_EQ(scene.surface(label).face, "+x");
  // The principal point is at (319.5, 239.5); pixel (320, 240) is 0.5 px off axis: on a plane
  // square to the axis, depth does not change across the face.
  EXPECT_NEAR(frame.depth.at(camera.width / 2, camera.height / 2), 1.5 - 0.125, 1e-6);
}

TEST(VirtualCamera, NothingBehindTheCameraOrOutsideTheRoom) {
  const Scene scene = LoadScene(SourcePath("configs/scenes/default.yaml"));
  const CameraIntrinsics camera = Xtion();
  const VirtualCamera virtual_camera(scene, camera, Exact());
  // Outside the room above the floor's edge, looking up into the sky: no surface at all.
  const RenderedFrame frame = virtual_camera.RenderExact(LookAt({-5.0, 0.0, 10.0}, {-5.0, 0.1, 30.0}));
  for (std::uint16_t label : frame.labels.pixels()) ASSERT_EQ(label, 0);
  for (float z : frame.depth.pixels()) ASSERT_EQ(z, 0.0f);
}

// Detects the scene's markers in a rendered image and checks each corner against its projection.
void ExpectMarkersDetectedWhereTheyAre(const std::string& scene_file, const Pose3& T_world_camera,
                                       size_t expected_count) {
  const Scene scene = LoadScene(scene_file);
  const CameraIntrinsics camera = Xtion();
  const VirtualCamera virtual_camera(scene, camera, Exact());
  const RenderedFrame frame = virtual_camera.RenderExact(T_world_camera);
  cv::Mat gray(camera.height, camera.width, CV_8UC1);
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) gray.at<std::uint8_t>(v, u) = frame.color.at(u, v)[1];
  }
  std::vector<int> ids;
  std::vector<std::vector<cv::Point2f>> corners;
  cv::aruco::detectMarkers(gray, cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_50), corners, ids);
  size_t checked = 0;
  for (const Marker& marker : scene.markers) {
    const auto it = std::find(ids.begin(), ids.end(), marker.id);
    if (it == ids.end()) continue;
    ++checked;
    // ArUco corner order: top-left, top-right, bottom-right, bottom-left of the marker image;
    // a mirrored or rotated texture would put them elsewhere.
    const auto& detected = corners[it - ids.begin()];
    const double h = marker.size / 2;
    const std::array<Eigen::Vector3d, 4> corners_world = {
        marker.center_world - h * marker.axis_u - h * marker.axis_v,
        marker.center_world + h * marker.axis_u - h * marker.axis_v,
        marker.center_world + h * marker.axis_u + h * marker.axis_v,
        marker.center_world - h * marker.axis_u + h * marker.axis_v};
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d expected = camera.Project(T_world_camera.inverse() * corners_world[k]);
      const Eigen::Vector2d found(detected[k].x, detected[k].y);
      EXPECT_LT((found - expected).norm(), 1.5) << "px, marker " << marker.id << " corner " << k;
    }
  }
  EXPECT_EQ(checked, expected_count) << "markers detected";
}

TEST(VirtualCamera, ArucoMarkersOnTheFloorAreDetectedWhereTheyAre) {
  // The two floor markers of the default scene, from the start of the walk.
  ExpectMarkersDetectedWhereTheyAre(SourcePath("configs/scenes/default.yaml"),
                                    LoadTrajectory(SourcePath("configs/walks/default.yaml")).front().T_world_camera, 2);
}

TEST(VirtualCamera, ArucoMarkersOnAVerticalBoxFaceAreDetectedUpright) {
  // The office scene: a marker rotated 90 deg on the floor and one on the box's +x face.
  const Scene scene = LoadScene(SourcePath("configs/scenes/office.yaml"));
  const Pose3& T_world_box = scene.object("box").T_world_object;
  const Eigen::Vector3d face = T_world_box.translation() + 0.15 * T_world_box.linear().col(0);
  const Eigen::Vector3d eye = face + 1.0 * T_world_box.linear().col(0) + Eigen::Vector3d(0, 0, 0.3);
  ExpectMarkersDetectedWhereTheyAre(SourcePath("configs/scenes/office.yaml"), LookAt(eye, face), 1);
  // From the room's start, looking down at the floor marker: both markers are in view.
  ExpectMarkersDetectedWhereTheyAre(SourcePath("configs/scenes/office.yaml"), LookAt({0, 0, 1.0}, {1.0, 0.3, 0}), 2);
}

TEST(VirtualCamera, ColourShowsFacesOfOneBoxInDifferentBrightness) {
  const Scene scene = LoadScene(SourcePath("configs/scenes/default.yaml"));
  const CameraIntrinsics camera = Xtion();
  const VirtualCamera virtual_camera(scene, camera, Exact());
  const RenderedFrame frame = virtual_camera.RenderExact(Viewpoints()[0]);
  std::map<std::string, double> brightness;
  std::map<std::string, int> count;
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const std::uint16_t label = frame.labels.at(u, v);
      if (label == 0 || scene.surface(label).object != "box") continue;
      brightness[scene.surface(label).face] += frame.color.at(u, v)[0];
      ++count[scene.surface(label).face];
    }
  }
  ASSERT_GE(brightness.size(), 3u) << "the box shows three faces from the start pose";
  std::vector<double> means;
  for (const auto& [face, sum] : brightness) {
    if (count[face] > 50) means.push_back(sum / count[face]);
  }
  std::sort(means.begin(), means.end());
  for (size_t i = 1; i < means.size(); ++i) EXPECT_GT(means[i] - means[i - 1], 3.0);
}

}  // namespace
}  // namespace planemap::sim
