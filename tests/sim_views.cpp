#include "sim_views.h"

#include <array>
#include <cmath>

#include "test_support.h"

namespace planemap::testing {

const sim::Scene& DefaultScene() {
  static const sim::Scene scene = sim::LoadScene(SourcePath("configs/scenes/default.yaml"));
  return scene;
}

const CameraIntrinsics& XtionCamera() {
  static const CameraIntrinsics camera = LoadCameraIntrinsics(SourcePath("configs/cameras/xtion_nao.yaml"));
  return camera;
}

namespace {

// Pixels of each face of a cuboid (+x, -x, +y, -y, +z, -z) in the exact render from `pose`.
std::array<int, 6> VisibleFacePixels(const sim::VirtualCamera& camera, const sim::Cuboid& cuboid, const Pose3& pose) {
  const sim::RenderedFrame frame = camera.RenderExact(pose);
  std::array<int, 6> visible{};
  for (std::uint16_t label : frame.labels.pixels()) {
    for (int f = 0; f < 6; ++f) visible[f] += label == cuboid.face_labels[f];
  }
  return visible;
}

}  // namespace

std::vector<Pose3> BoxViewpoints() {
  static const std::vector<Pose3> poses = [] {
    const sim::Scene& scene = DefaultScene();
    const sim::SceneObject& box = scene.object("box");
    const sim::Cuboid& cuboid = scene.cuboids[box.cuboids[0]];
    const Eigen::Vector3d center = box.T_world_object.translation();
    // The box's +x and -y faces both face bearing yaw - 45 deg from its centre.
    const Eigen::Vector3d x_axis = box.T_world_object.linear().col(0);
    const double diagonal = std::atan2(x_axis.y(), x_axis.x()) - M_PI / 4;
    sim::RenderConfig exact;
    exact.add_noise = false;
    const sim::VirtualCamera camera(scene, XtionCamera(), exact);
    std::vector<Pose3> selected;
    for (double distance : {1.0, 1.5, 2.0, 2.5, 3.0}) {
      for (double offset_deg : {-20.0, -10.0, 0.0, 10.0, 20.0}) {
        for (double height : {0.7, 1.0, 1.3}) {
          const double b = diagonal + offset_deg * M_PI / 180.0;
          const Eigen::Vector3d eye = center + Eigen::Vector3d(distance * std::cos(b), distance * std::sin(b), 0.0);
          const Pose3 pose = LookAt(Eigen::Vector3d(eye.x(), eye.y(), height), center);
          // Keep the view if the two sides (+x, -y) and the top each show 1500+ pixels.
          const std::array<int, 6> visible = VisibleFacePixels(camera, cuboid, pose);
          if (visible[0] >= 1500 && visible[3] >= 1500 && visible[4] >= 1500) selected.push_back(pose);
        }
      }
    }
    return selected;
  }();
  return poses;
}

std::vector<Pose3> BoxTwoFaceViewpoints() {
  static const std::vector<Pose3> poses = [] {
    const sim::Scene& scene = DefaultScene();
    const sim::SceneObject& box = scene.object("box");
    const sim::Cuboid& cuboid = scene.cuboids[box.cuboids[0]];
    const Eigen::Vector3d center = box.T_world_object.translation();
    const Eigen::Vector3d x_axis = box.T_world_object.linear().col(0), y_axis = box.T_world_object.linear().col(1);
    auto bearing = [](const Eigen::Vector3d& d) { return std::atan2(d.y(), d.x()); };
    sim::RenderConfig exact;
    exact.add_noise = false;
    const sim::VirtualCamera camera(scene, XtionCamera(), exact);
    // Faces by label index: +x 0, -x 1, +y 2, -y 3, +z 4, -z 5.
    struct Family {
      double bearing;
      std::vector<double> offsets_deg, heights;
      std::array<int, 2> faces;
    };
    const std::vector<Family> families{
        {bearing(x_axis), {-4.0, -2.0, 0.0, 2.0, 4.0}, {0.7, 1.0, 1.3}, {0, 4}},    // top and +x side
        {bearing(-y_axis), {-4.0, -2.0, 0.0, 2.0, 4.0}, {0.7, 1.0, 1.3}, {3, 4}},   // top and -y side
        {bearing(x_axis) - M_PI / 4, {-20.0, -10.0, 0.0, 10.0, 20.0}, {0.12, 0.18}, {0, 3}},  // two sides
    };
    std::vector<Pose3> selected;
    for (const Family& family : families) {
      for (double distance : {1.0, 1.5, 2.0, 2.5, 3.0}) {
        for (double offset_deg : family.offsets_deg) {
          for (double height : family.heights) {
            const double b = family.bearing + offset_deg * M_PI / 180.0;
            const Eigen::Vector3d eye = center + Eigen::Vector3d(distance * std::cos(b), distance * std::sin(b), 0.0);
            const Pose3 pose = LookAt(Eigen::Vector3d(eye.x(), eye.y(), height), center);
            const std::array<int, 6> visible = VisibleFacePixels(camera, cuboid, pose);
            bool two = true;
            for (int f = 0; f < 6; ++f) {
              const bool shown = f == family.faces[0] || f == family.faces[1];
              two = two && (shown ? visible[f] >= 1500 : visible[f] < 100);
            }
            if (two) selected.push_back(pose);
          }
        }
      }
    }
    return selected;
  }();
  return poses;
}

SimFrame RenderDefaultScene(const Pose3& T_world_camera, std::uint64_t seed, bool noise) {
  sim::RenderConfig config;
  config.add_noise = noise;
  const sim::VirtualCamera camera(DefaultScene(), XtionCamera(), config);
  sim::RenderedFrame rendered = camera.Render(T_world_camera, seed);
  SimFrame sim;
  sim.frame.depth = std::move(rendered.depth);
  sim.frame.color = std::move(rendered.color);
  sim.frame.T_world_camera = T_world_camera;
  sim.labels = std::move(rendered.labels);
  const Pose3 T_camera_world = T_world_camera.inverse();
  for (const sim::Surface& s : DefaultScene().surfaces) sim.planes_camera[s.label] = TransformPlane(T_camera_world, s.plane_world);
  return sim;
}

}  // namespace planemap::testing
