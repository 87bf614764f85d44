// planemap render: a simulated RGB-D sequence in the TUM layout, with exact ground truth.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <spdlog/spdlog.h>

#include "app_report.h"
#include "planemap/apps/app_config.h"
#include "planemap/apps/commands.h"
#include "planemap/apps/depth_summary.h"
#include "planemap/core/error.h"
#include "planemap/io/image_io.h"
#include "planemap/io/tum_sequence.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/virtual_camera.h"
#include "planemap/sim/walk.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

void WriteMetadata(const std::string& out, const std::string& scene_file, const sim::Scene& scene,
                   const AppConfig& config) {
  const fs::path root(out);
  std::error_code ec;
  fs::copy_file(scene_file, root / "scene.yaml", fs::copy_options::overwrite_existing, ec);
  if (ec) ThrowInputError((root / "scene.yaml").string(), 0, "cannot copy the scene: " + ec.message());
  SaveYamlFile(sim::SceneGroundTruth(scene), (root / "scene_groundtruth.yaml").string());
  SaveYamlFile(ConfigToYaml(config), (root / "config.yaml").string());
}

}  // namespace

int RunRender(const RenderOptions& options) {
  const std::string scene_file = ResolveConfigPath(options.scene);
  const sim::Scene scene = sim::LoadScene(scene_file);
  const CameraIntrinsics camera = LoadCameraIntrinsics(ResolveConfigPath(options.camera));
  AppConfig config = LoadConfigFile<AppConfig>(ResolveConfigPath(options.config));
  if (options.seed >= 0) config.render.seed = options.seed;
  if (options.exact) config.render.add_noise = false;
  Trajectory trajectory = sim::LoadTrajectory(ResolveConfigPath(options.trajectory));
  if (trajectory.empty()) ThrowInputError(options.trajectory, 0, "the trajectory has no poses");
  if (options.max_frames >= 0 && static_cast<size_t>(options.max_frames) < trajectory.size()) {
    trajectory.resize(options.max_frames);
  }

  const sim::VirtualCamera virtual_camera(scene, camera, config.render);
  TumSequenceWriter writer(options.out, camera, /*with_labels=*/true);
  WriteMetadata(options.out, scene_file, scene, config);

  DepthSummary stats;
  size_t too_far = 0;  // pixels past the PNG's range: 65535 units of camera.depth_scale
  const auto start = std::chrono::steady_clock::now();
  const size_t report_every = std::max<size_t>(1, trajectory.size() / 10);
  for (size_t k = 0; k < trajectory.size(); ++k) {
    const StampedPose& pose = trajectory[k];
    std::optional<Pose3> exposure_start;
    if (config.render.noise.motion_blur) {
      exposure_start = PoseAt(trajectory, pose.stamp - config.render.noise.exposure, 1e9);
    }
    sim::RenderedFrame rendered =
        virtual_camera.Render(pose.T_world_camera, virtual_camera.FrameSeed(static_cast<int>(k)), exposure_start);
    RgbdFrame frame;
    frame.index = static_cast<int>(k);
    frame.stamp = frame.color_stamp = pose.stamp;
    frame.depth = std::move(rendered.depth);
    frame.color = std::move(rendered.color);
    frame.T_world_camera = pose.T_world_camera;
    // What the 16-bit PNG cannot hold is written as no depth: counted here as such.
    too_far += ClearDepthBeyondPng(&frame.depth, camera.depth_scale);
    stats.Add(frame.depth);
    writer.Add(frame, &rendered.labels);
    if ((k + 1) % report_every == 0 || k + 1 == trajectory.size()) {
      spdlog::info("rendered {}/{} frames", k + 1, trajectory.size());
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const size_t n = trajectory.size();
  std::printf("planemap render: wrote %zu frames (%.1f s of %s) to %s\n", n,
              trajectory.back().stamp - trajectory.front().stamp, fs::path(options.trajectory).filename().c_str(),
              options.out.c_str());
  std::printf("  scene %s: %zu objects, %zu surfaces, %zu markers\n", scene.name.c_str(), scene.objects.size(),
              scene.surfaces.size(), scene.markers.size());
  std::printf("  camera %dx%d fx %.1f, noise %s, seed %d\n", camera.width, camera.height, camera.fx,
              config.render.add_noise ? "on" : "off", config.render.seed);
  if (stats.z_max > 0.0) {
    std::printf("  depth: %.1f%% of pixels valid on average, %.2f-%.2f m\n", stats.MeanValidPercent(), stats.z_min, stats.z_max);
  } else {
    std::printf("  depth: no valid pixel\n");
  }
  if (too_far > 0) {
    std::printf("  %.1f%% of pixels were farther than a 16-bit depth PNG holds at depth_scale %g (%.3f m): written as no depth\n",
                100.0 * too_far / (static_cast<double>(n) * camera.width * camera.height), camera.depth_scale,
                65535.0 / camera.depth_scale);
  }
  if (too_far > 0 && stats.MeanValidPercent() == 0.0) {
    ThrowInputError(options.camera, 0, "depth_scale " + Printf("%g", camera.depth_scale) +
                                           " units per metre leaves no depth a 16-bit PNG can hold: every depth image written is empty");
  }
  std::printf("  files: rgb/ depth/ label/ rgb.txt depth.txt label.txt associations.txt groundtruth.txt\n");
  std::printf("         scene.yaml scene_groundtruth.yaml camera.yaml config.yaml\n");
  std::printf("  %.1f ms per frame (render + PNG)\n", 1000.0 * seconds / n);
  return 0;
}

}  // namespace planemap
