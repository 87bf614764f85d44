#pragma once
// RGB-D sequences in the TUM RGB-D benchmark layout:
//   rgb/<stamp>.png    8-bit colour          rgb.txt          "stamp rgb/<stamp>.png"
//   depth/<stamp>.png  16-bit depth          depth.txt        "stamp depth/<stamp>.png"
//   groundtruth.txt    optional, "stamp tx ty tz qx qy qz qw" (world <- colour camera)
// Simulated sequences also carry label/<stamp>.png (16-bit surface ids) and label.txt.
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/intrinsics.h"
#include "planemap/core/rgbd_frame.h"
#include "planemap/core/tum_format.h"

namespace planemap {

struct DatasetConfig {
  double max_association_gap = 0.02;  // colour/depth pairs further apart are not associated [s]
  double max_groundtruth_gap = 0.02;  // a frame further from any ground-truth pose gets none [s]

  template <class V>
  void VisitFields(V&& v) {
    v("max_association_gap", max_association_gap, Check::kPositive);
    v("max_groundtruth_gap", max_groundtruth_gap, Check::kPositive);
  }
};

class TumSequence {
 public:
  struct Entry {
    StampedFile depth;
    StampedFile color;
    std::optional<StampedFile> label;
    std::optional<Pose3> T_world_camera;  // ground truth at the depth stamp
  };

  // Reads the lists and ground truth of `dir`. Throws InputError naming the file and line for a
  // missing folder or list, a malformed line, or a sequence without a single colour/depth pair.
  // A sequence planemap wrote carries its camera in camera.yaml; a `camera` that differs from it
  // (say, a depth scale of 1000 for a sequence written with 5000) is an error, not a silent
  // misreading of every depth.
  static TumSequence Open(const std::string& dir, const CameraIntrinsics& camera,
                          const DatasetConfig& config = {});

  // The camera stored with a sequence (dir/camera.yaml), if there is one.
  static std::optional<CameraIntrinsics> StoredCamera(const std::string& dir);

  size_t size() const { return entries_.size(); }
  const std::string& dir() const { return dir_; }
  const CameraIntrinsics& camera() const { return camera_; }
  const Entry& entry(size_t i) const { return entries_.at(i); }
  bool has_groundtruth() const { return !groundtruth_.empty(); }
  const Trajectory& groundtruth() const { return groundtruth_; }
  bool has_labels() const { return has_labels_; }

  // Loads frame i: depth in metres (0 = no measurement). Throws InputError naming the image and
  // the list line that refers to it when the image is missing, unreadable, of the wrong pixel
  // format (e.g. 8-bit depth) or of another size than the camera.
  RgbdFrame LoadFrame(size_t i) const;

  // Per-pixel surface labels of a simulated frame; throws InputError if the sequence has none.
  LabelImage LoadLabels(size_t i) const;

 private:
  std::string dir_;
  CameraIntrinsics camera_;
  std::vector<Entry> entries_;
  Trajectory groundtruth_;
  bool has_labels_ = false;
};

// Writes a sequence frame by frame. Every list line is flushed as its frame is written, so an
// interrupted run leaves a readable sequence of the frames written so far.
class TumSequenceWriter {
 public:
  // Creates `dir` with rgb/ and depth/ (and label/ when `with_labels`) and writes camera.yaml.
  TumSequenceWriter(const std::string& dir, const CameraIntrinsics& camera, bool with_labels);

  // Writes one frame; its ground-truth pose goes to groundtruth.txt when present.
  void Add(const RgbdFrame& frame, const LabelImage* labels = nullptr);

  size_t frames_written() const { return frames_written_; }

 private:
  void AppendLine(std::ofstream& list, const std::string& file, const std::string& line);

  std::string dir_;
  CameraIntrinsics camera_;
  bool with_labels_;
  size_t frames_written_ = 0;
  std::ofstream rgb_list_, depth_list_, label_list_, associations_, groundtruth_;
};

}  // namespace planemap
