#include "frontend_frames.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "planemap/core/error.h"
#include "planemap/frontend/osd_labels.h"
#include "planemap/frontend/pcd_source.h"
#include "planemap/io/tum_sequence.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/virtual_camera.h"
#include "planemap/sim/walk.h"
#include "real_table.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

constexpr int kOsdScenes = 25;  // learn0-24: boxes, then stacked boxes

// The cloud the segmenters take, and which of its pixels hold a point.
void AddCloud(const CameraIntrinsics& camera, BenchFrame* f) {
  if (!f->cloud) f->cloud = MakeOrganizedCloud(f->rgbd, camera, CloudConfig{});
  f->valid.resize(f->cloud->size());
  for (size_t i = 0; i < f->cloud->size(); ++i) f->valid[i] = IsValidPoint((*f->cloud)[i]);
}

// The depth image of an organized cloud: each point's z, 0 where there is none.
DepthImage DepthOf(const Cloud& cloud) {
  DepthImage depth(static_cast<int>(cloud.width), static_cast<int>(cloud.height), 0.0f);
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (IsValidPoint(cloud[i])) depth.pixels()[i] = cloud[i].z;
  }
  return depth;
}

}  // namespace

const FrameSet& LazyFrameSet::Get() {
  if (!frames_) frames_ = std::make_unique<FrameSet>(load_());
  return *frames_;
}

FrameSet RenderedFrames(const std::string& source_dir) {
  const std::string configs = source_dir + "/configs/";
  FrameSet set;
  set.name = "rendered";
  set.camera = LoadCameraIntrinsics(configs + "cameras/xtion_nao.yaml");
  const sim::Scene scene = sim::LoadScene(configs + "scenes/default.yaml");
  const sim::VirtualCamera virtual_camera(scene, set.camera, sim::RenderConfig{});
  const Trajectory walk = sim::LoadTrajectory(configs + "walks/default.yaml");
  for (size_t k = 0; k < kFramesPerSequence; ++k) {
    const Pose3& T = walk[k * (walk.size() - 1) / (kFramesPerSequence - 1)].T_world_camera;
    sim::RenderedFrame r = virtual_camera.Render(T, virtual_camera.FrameSeed(static_cast<int>(k)));
    BenchFrame f;
    f.rgbd.depth = std::move(r.depth);
    f.rgbd.color = std::move(r.color);
    f.labels = std::move(r.labels);
    for (const sim::Surface& s : scene.surfaces)
      f.planes_camera[s.label] = TransformPlane(T.inverse(), s.plane_world);
    AddCloud(set.camera, &f);
    set.frames.push_back(std::move(f));
  }
  return set;
}

FrameSet SequenceFrames(const std::string& name, const std::string& dir, const CameraIntrinsics& camera) {
  const TumSequence sequence = TumSequence::Open(dir, camera);
  FrameSet set;
  set.name = name;
  set.camera = camera;
  const size_t count = std::min(kFramesPerSequence, sequence.size());
  for (size_t k = 0; k < count; ++k) {
    BenchFrame f;
    f.rgbd = sequence.LoadFrame(count > 1 ? k * (sequence.size() - 1) / (count - 1) : 0);
    AddCloud(camera, &f);
    set.frames.push_back(std::move(f));
  }
  return set;
}

FrameSet OsdFrames(const std::string& name, const std::string& pcd_dir, const CameraIntrinsics& camera,
                   int scenes) {
  FrameSet set;
  set.name = name;
  set.camera = camera;
  set.from_cloud = true;
  for (int k = 0; k < scenes; ++k) {
    PcdFrame pcd = LoadOrganizedPcd(pcd_dir + "/learn" + std::to_string(k) + ".pcd", camera);
    BenchFrame f;
    f.rgbd.index = k;
    f.rgbd.depth = DepthOf(*pcd.cloud);
    f.rgbd.color = std::move(pcd.color);
    LabelledSurfaces surfaces = OsdSurfaces(*pcd.cloud, pcd.labels);
    f.labels = std::move(surfaces.labels);
    f.planes_camera = std::move(surfaces.planes_camera);
    f.cloud = std::move(pcd.cloud);
    AddCloud(camera, &f);
    set.frames.push_back(std::move(f));
  }
  return set;
}

std::vector<std::unique_ptr<LazyFrameSet>> FindFrameSets(const std::string& source_dir,
                                                         const std::string& data_dir) {
  std::vector<std::unique_ptr<LazyFrameSet>> sets;
  sets.push_back(std::make_unique<LazyFrameSet>(
      "rendered", "12 frames of the default walk (full noise model), xtion_nao.yaml; the simulator's labels",
      [source_dir] { return RenderedFrames(source_dir); }));
  std::vector<RealSequence> sequences;
  try {
    sequences = FindRealSequences(data_dir);
  } catch (const InputError& e) {
    std::fprintf(stderr, "bench_frontend: %s: rendered frames only\n", e.what());
    return sets;
  }
  for (const RealSequence& s : sequences) {
    const std::optional<std::string> camera_file = CameraFileByName(s.name);
    if (!camera_file) {
      std::fprintf(stderr, "bench_frontend: %s left out: no camera by its name\n", s.name.c_str());
      continue;
    }
    const CameraIntrinsics camera = LoadCameraIntrinsics(source_dir + "/" + *camera_file);
    const size_t frames = TumSequence::Open(s.dir, camera).size();
    if (frames < kFramesPerSequence) {
      std::fprintf(stderr, "bench_frontend: %s left out: %zu frames\n", s.name.c_str(), frames);
      continue;
    }
    const std::string what = std::to_string(kFramesPerSequence) + " of its " + std::to_string(frames) +
                             " frames, evenly spaced, first to last, " +
                             fs::path(*camera_file).filename().string() + "; no labels";
    sets.push_back(std::make_unique<LazyFrameSet>(
        s.name, what, [s, camera] { return SequenceFrames(s.name, s.dir, camera); }));
  }
  const std::string osd = data_dir + "/osd_boxes_learn/pcd";
  if (fs::is_regular_file(osd + "/learn" + std::to_string(kOsdScenes - 1) + ".pcd")) {
    const CameraIntrinsics camera =
        LoadCameraIntrinsics(source_dir + "/configs/cameras/tum_openni_default.yaml");
    const std::string what =
        "osd_boxes_learn's learn0-" + std::to_string(kOsdScenes - 1) +
        " (boxes, stacked boxes), tum_openni_default.yaml. The frames are the\n"
        "    files' clouds: the whole frontend rows start from them (no depth to cloud: add that row for a\n"
        "    depth image), the cloud row and OpenCV take the depth image of their z. The labelled surfaces\n"
        "    are the table (labels 1-9) and the boxes' faces (labels 20+, a box per ten): planes of 400\n"
        "    points or more within 5 mm through each one's labelled points by PCL's RANSAC, each its\n"
        "    largest 4-connected piece, refitted (frontend/osd_labels.h, as test_real_frames judges boxes)";
    sets.push_back(std::make_unique<LazyFrameSet>(
        "osd", what, [osd, camera] { return OsdFrames("osd", osd, camera, kOsdScenes); }));
  } else {
    std::fprintf(stderr, "bench_frontend: osd left out: no %s/learn0-%d.pcd\n", osd.c_str(), kOsdScenes - 1);
  }
  return sets;
}

}  // namespace planemap
