#pragma once
// The frame sets bench_frontend runs every method on: rendered frames of the default walk (labels
// from the simulator), 12 frames of each real TUM-layout sequence (no labels), and the OSD boxes
// (labels from each point's object label, osd_labels.h).
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "planemap/core/image.h"
#include "planemap/core/intrinsics.h"
#include "planemap/core/plane.h"
#include "planemap/core/rgbd_frame.h"
#include "planemap/frontend/organized_cloud.h"

namespace planemap {

struct BenchFrame {
  RgbdFrame rgbd;                                // depth [m], 0 = none; OSD's from its cloud's z
  Cloud::Ptr cloud;                              // what the segmenters take: made from rgbd, or OSD's file
  std::vector<bool> valid;                       // pixels with a point
  LabelImage labels;                             // labelled surfaces; empty without labels
  std::map<std::uint16_t, Plane> planes_camera;  // each labelled surface's plane
};

struct FrameSet {
  std::string name;
  CameraIntrinsics camera;
  std::vector<BenchFrame> frames;
  bool from_cloud = false;  // the frames are clouds (OSD): the whole frontend starts from them
  bool labelled() const { return !frames.empty() && !frames.front().labels.empty(); }
};

// A frame set by name, loaded on first use (a run filtered to one set loads only that one).
class LazyFrameSet {
 public:
  LazyFrameSet(std::string name, std::string what, std::function<FrameSet()> load)
      : name_(std::move(name)), what_(std::move(what)), load_(std::move(load)) {}
  const std::string& name() const { return name_; }
  const std::string& what() const { return what_; }  // where its frames come from, for the table's notes
  const FrameSet& Get();

 private:
  std::string name_, what_;
  std::function<FrameSet()> load_;
  std::unique_ptr<FrameSet> frames_;
};

constexpr size_t kFramesPerSequence = 12;

// The 12 frames of the default walk toward the box (full noise model) through xtion_nao.yaml.
FrameSet RenderedFrames(const std::string& source_dir);

// kFramesPerSequence frames evenly spaced over the sequence in `dir`, from the first to the last.
FrameSet SequenceFrames(const std::string& name, const std::string& dir, const CameraIntrinsics& camera);

// The first `scenes` OSD scenes in `pcd_dir` (learn0.pcd, learn1.pcd, ...) through `camera`
// (tum_openni_default.yaml): the files' clouds, depth images of their z, and the table and boxes'
// faces as labelled surfaces (OsdSurfaces).
FrameSet OsdFrames(const std::string& name, const std::string& pcd_dir, const CameraIntrinsics& camera,
                   int scenes);

// The sets under `data_dir`: `rendered`, each TUM-layout sequence with ground truth and at least
// kFramesPerSequence frames whose camera follows from its name (real_table.h, CameraFileByName),
// and `osd` when data_dir/osd_boxes_learn/pcd holds the scenes. What is left out is said on stderr.
std::vector<std::unique_ptr<LazyFrameSet>> FindFrameSets(const std::string& source_dir,
                                                         const std::string& data_dir);

}  // namespace planemap
