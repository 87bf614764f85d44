// planemap frame: the frontend on one frame; the model as JSON, an overlay PNG and a PLY.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "planemap/apps/app_config.h"
#include "planemap/apps/commands.h"
#include "planemap/core/error.h"
#include "planemap/frontend/frontend.h"
#include "planemap/frontend/pcd_source.h"
#include "planemap/io/frame_model_io.h"
#include "planemap/io/image_io.h"
#include "planemap/io/tum_sequence.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

CameraIntrinsics ChooseCamera(const FrameOptions& options) {
  if (!options.camera.empty()) return LoadCameraIntrinsics(ResolveConfigPath(options.camera));
  if (!options.sequence.empty()) {
    if (const auto stored = TumSequence::StoredCamera(options.sequence)) return *stored;
  }
  return LoadCameraIntrinsics(ResolveConfigPath("configs/cameras/tum_openni_default.yaml"));
}

}  // namespace

int RunFrame(const FrameOptions& options) {
  const int sources = !options.sequence.empty() + !options.depth.empty() + !options.pcd.empty();
  if (sources != 1) throw InputError("give exactly one frame source: --sequence DIR (with --index), --depth PNG or --pcd FILE");
  const CameraIntrinsics camera = ChooseCamera(options);
  const AppConfig config = LoadConfigFile<AppConfig>(ResolveConfigPath(options.config));
  const Frontend frontend(camera, config.frontend, LoadPatterns(ResolveConfigPath(options.patterns)));

  RgbdFrame frame;
  Cloud::Ptr cloud;
  std::string source;
  if (!options.sequence.empty()) {
    const TumSequence sequence = TumSequence::Open(options.sequence, camera, config.dataset);
    if (options.index < 0 || static_cast<size_t>(options.index) >= sequence.size()) {
      ThrowInputError(options.sequence, 0, "frame " + std::to_string(options.index) + " does not exist (" +
                                               std::to_string(sequence.size()) + " frames)");
    }
    frame = sequence.LoadFrame(options.index);
    source = options.sequence + " frame " + std::to_string(options.index);
  } else if (!options.depth.empty()) {
    frame.depth = ReadDepthPng(options.depth, camera);
    if (!options.color.empty()) frame.color = ReadColorPng(options.color, camera);
    source = options.depth;
  } else {
    PcdFrame pcd = LoadOrganizedPcd(options.pcd, camera);
    cloud = pcd.cloud;
    frame.color = std::move(pcd.color);
    source = options.pcd;
  }
  if (!cloud) cloud = MakeOrganizedCloud(frame, camera, config.frontend.cloud);
  const FrameModel model = frontend.Process(*cloud);

  std::error_code ec;
  fs::create_directories(options.out, ec);
  if (ec) ThrowInputError(options.out, 0, "cannot create folder: " + ec.message());
  const std::string json = FrameModelJson(model);
  std::ofstream(fs::path(options.out) / "model.json") << json << "\n";
  std::vector<Eigen::Vector3f> points(cloud->size());
  for (size_t i = 0; i < cloud->size(); ++i) points[i] = (*cloud)[i].getVector3fMap();
  WriteFrameModelPly((fs::path(options.out) / "model.ply").string(), model, points);
  WriteOverlayPng((fs::path(options.out) / "overlay.png").string(), frame.color, model, camera);

  std::printf("%s\n", json.c_str());
  std::fprintf(stderr, "planemap frame: %s: %zu planes, %zu intersections, %zu trihedral angles, %zu objects%s%s\n",
               source.c_str(), model.planes.size(), model.edges.size(), model.angles.size(), model.objects.size(),
               model.reason.empty() ? "" : "; ", model.reason.c_str());
  std::fprintf(stderr, "  wrote %s/model.json, model.ply, overlay.png\n", options.out.c_str());
  return 0;
}

}  // namespace planemap
