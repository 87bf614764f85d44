#include "planemap/io/tum_sequence.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "planemap/core/error.h"
#include "planemap/io/image_io.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

std::vector<double> Stamps(const std::vector<StampedFile>& files) {
  std::vector<double> stamps;
  stamps.reserve(files.size());
  for (const StampedFile& f : files) stamps.push_back(f.stamp);
  return stamps;
}

std::string ListRef(const std::string& dir, const char* list, const StampedFile& f) {
  return (fs::path(dir) / list).string() + ":" + std::to_string(f.line);
}

bool SameCamera(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  auto same = [](double x, double y) { return std::abs(x - y) <= 1e-9 * std::max(1.0, std::abs(x)); };
  return same(a.fx, b.fx) && same(a.fy, b.fy) && same(a.cx, b.cx) && same(a.cy, b.cy) && a.width == b.width &&
         a.height == b.height && same(a.depth_scale, b.depth_scale);
}

}  // namespace

std::optional<CameraIntrinsics> TumSequence::StoredCamera(const std::string& dir) {
  const fs::path file = fs::path(dir) / "camera.yaml";
  std::error_code ec;
  if (!fs::exists(file, ec)) return std::nullopt;
  return LoadCameraIntrinsics(file.string());
}

TumSequence TumSequence::Open(const std::string& dir, const CameraIntrinsics& camera,
                              const DatasetConfig& config) {
  ValidateConfig(camera, "camera.");
  ValidateConfig(config, "dataset.");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) ThrowInputError(dir, 0, "sequence folder does not exist");
  const fs::path root(dir);
  if (const std::optional<CameraIntrinsics> stored = StoredCamera(dir)) {
    if (!SameCamera(*stored, camera)) {
      ThrowInputError((root / "camera.yaml").string(), 0,
                      "the sequence was written with another camera (fx " + std::to_string(stored->fx) +
                          ", depth_scale " + std::to_string(stored->depth_scale) + ") than the one given (fx " +
                          std::to_string(camera.fx) + ", depth_scale " + std::to_string(camera.depth_scale) +
                          "); use this camera.yaml");
    }
  }
  const std::vector<StampedFile> rgb = ReadFileList((root / "rgb.txt").string());
  const std::vector<StampedFile> depth = ReadFileList((root / "depth.txt").string());

  TumSequence sequence;
  sequence.dir_ = dir;
  sequence.camera_ = camera;
  if (fs::exists(root / "groundtruth.txt", ec)) {
    sequence.groundtruth_ = ReadTumTrajectory((root / "groundtruth.txt").string());
  }
  std::vector<StampedFile> labels;
  if (fs::exists(root / "label.txt", ec)) {
    labels = ReadFileList((root / "label.txt").string());
    sequence.has_labels_ = true;
  }

  const auto pairs = AssociateStamps(Stamps(depth), Stamps(rgb), config.max_association_gap);
  if (pairs.empty()) {
    ThrowInputError((root / "depth.txt").string(), 0,
                    "no depth image has a colour image within " +
                        std::to_string(config.max_association_gap) + " s (" +
                        std::to_string(depth.size()) + " depth, " + std::to_string(rgb.size()) +
                        " colour entries)");
  }
  // Labels are written with the depth stamp; match them exactly (to the printed microsecond).
  const auto label_pairs = AssociateStamps(Stamps(depth), Stamps(labels), 5e-7);
  std::vector<int> label_of_depth(depth.size(), -1);
  for (const auto& [d, l] : label_pairs) label_of_depth[d] = static_cast<int>(l);

  for (const auto& [d, c] : pairs) {
    Entry entry;
    entry.depth = depth[d];
    entry.color = rgb[c];
    if (label_of_depth[d] >= 0) entry.label = labels[label_of_depth[d]];
    entry.T_world_camera = PoseAt(sequence.groundtruth_, depth[d].stamp, config.max_groundtruth_gap);
    sequence.entries_.push_back(std::move(entry));
  }
  return sequence;
}

RgbdFrame TumSequence::LoadFrame(size_t i) const {
  if (i >= entries_.size()) {
    ThrowInputError(dir_, 0, "frame " + std::to_string(i) + " does not exist (" +
                                 std::to_string(entries_.size()) + " frames)");
  }
  const Entry& e = entries_[i];
  const fs::path root(dir_);
  RgbdFrame frame;
  frame.index = static_cast<int>(i);
  frame.stamp = e.depth.stamp;
  frame.color_stamp = e.color.stamp;
  frame.depth = ReadDepthPng((root / e.depth.path).string(), camera_, ListRef(dir_, "depth.txt", e.depth));
  frame.color = ReadColorPng((root / e.color.path).string(), camera_, ListRef(dir_, "rgb.txt", e.color));
  frame.T_world_camera = e.T_world_camera;
  return frame;
}

LabelImage TumSequence::LoadLabels(size_t i) const {
  const Entry& e = entries_.at(i);
  if (!e.label) ThrowInputError(dir_, 0, "frame " + std::to_string(i) + " has no label image");
  return ReadLabelPng((fs::path(dir_) / e.label->path).string(), camera_,
                      ListRef(dir_, "label.txt", *e.label));
}

TumSequenceWriter::TumSequenceWriter(const std::string& dir, const CameraIntrinsics& camera,
                                     bool with_labels)
    : dir_(dir), camera_(camera), with_labels_(with_labels) {
  ValidateConfig(camera, "camera.");
  std::error_code ec;
  const fs::path root(dir);
  for (const char* sub : {"rgb", "depth", "label"}) {
    if (std::string(sub) == "label" && !with_labels) continue;
    fs::create_directories(root / sub, ec);
    if (ec) ThrowInputError((root / sub).string(), 0, "cannot create folder: " + ec.message());
  }
  SaveYamlFile(ConfigToYaml(camera), (root / "camera.yaml").string());
  auto open = [&](std::ofstream& out, const char* name, const char* header) {
    out.open(root / name);
    if (!out) ThrowInputError((root / name).string(), 0, "cannot open file for writing");
    out << header;
    out.flush();
  };
  open(rgb_list_, "rgb.txt", "# color images\n# written by planemap\n# timestamp filename\n");
  open(depth_list_, "depth.txt", "# depth maps\n# written by planemap\n# timestamp filename\n");
  open(associations_, "associations.txt", "");
  open(groundtruth_, "groundtruth.txt", "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n");
  if (with_labels_) open(label_list_, "label.txt", "# surface labels (16-bit, 0 = none)\n# timestamp filename\n");
}

void TumSequenceWriter::AppendLine(std::ofstream& list, const std::string& file, const std::string& line) {
  list << line << '\n';
  list.flush();
  if (!list) ThrowInputError((fs::path(dir_) / file).string(), 0, "write failed");
}

void TumSequenceWriter::Add(const RgbdFrame& frame, const LabelImage* labels) {
  const fs::path root(dir_);
  const std::string depth_name = FormatStamp(frame.stamp);
  const std::string color_name = FormatStamp(frame.color_stamp);
  const std::string rgb_path = "rgb/" + color_name + ".png";
  const std::string depth_path = "depth/" + depth_name + ".png";
  WriteColorPng((root / rgb_path).string(), frame.color);
  WriteDepthPng((root / depth_path).string(), frame.depth, camera_.depth_scale);
  if (with_labels_) {
    if (labels == nullptr) ThrowInputError(dir_, 0, "frame " + std::to_string(frame.index) + " has no labels");
    const std::string label_path = "label/" + depth_name + ".png";
    WriteLabelPng((root / label_path).string(), *labels);
    AppendLine(label_list_, "label.txt", depth_name + " " + label_path);
  }
  AppendLine(rgb_list_, "rgb.txt", color_name + " " + rgb_path);
  AppendLine(depth_list_, "depth.txt", depth_name + " " + depth_path);
  AppendLine(associations_, "associations.txt",
             color_name + " " + rgb_path + " " + depth_name + " " + depth_path);
  if (frame.T_world_camera) {
    AppendLine(groundtruth_, "groundtruth.txt", FormatTumPose({frame.stamp, *frame.T_world_camera}));
  }
  ++frames_written_;
}

}  // namespace planemap
