// TUM RGB-D sequences: real data, write/read round trips, and bad input that names the file.
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "planemap/core/error.h"
#include "planemap/core/intrinsics.h"
#include "planemap/io/image_io.h"
#include "planemap/io/tum_sequence.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

using planemap::testing::PosesNear;
using planemap::testing::SharedPath;
using planemap::testing::SourcePath;
using planemap::testing::TempDir;
using planemap::testing::ThrowsWith;

constexpr double kRadToDeg = 180.0 / M_PI;

CameraIntrinsics OpenNiCamera() {
  return LoadCameraIntrinsics(SourcePath("configs/cameras/tum_openni_default.yaml"));
}

struct DepthStats {
  double valid_fraction = 0.0;
  float min = std::numeric_limits<float>::infinity();  // [m] over valid pixels
  float max = 0.0f;                                    // [m]
  int invalid_nonzero = 0;                             // pixels neither 0 nor valid (NaN, negative)
};

DepthStats Stats(const DepthImage& depth) {
  DepthStats stats;
  size_t valid = 0;
  for (float z : depth.pixels()) {
    if (IsValidDepth(z)) {
      ++valid;
      stats.min = std::min(stats.min, z);
      stats.max = std::max(stats.max, z);
    } else if (z != 0.0f) {
      ++stats.invalid_nonzero;
    }
  }
  stats.valid_fraction = static_cast<double>(valid) / depth.size();
  return stats;
}

// Stamp pairs (rgb, depth) of an associations.txt written by TUM's associate.py.
std::vector<std::pair<double, double>> ReadAssociations(const std::string& file) {
  std::ifstream in(file);
  std::vector<std::pair<double, double>> pairs;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double rgb = 0.0, depth = 0.0;
    std::string rgb_path, depth_path;
    fields >> rgb >> rgb_path >> depth >> depth_path;
    pairs.emplace_back(rgb, depth);
  }
  return pairs;
}

void ExpectAssociationsLikeAssociatePy(const TumSequence& sequence, const std::string& associations_file) {
  const auto expected = ReadAssociations(associations_file);
  ASSERT_EQ(sequence.size(), expected.size());
  for (size_t i = 0; i < sequence.size(); ++i) {
    EXPECT_NEAR(sequence.entry(i).color.stamp, expected[i].first, 1e-6) << "pair " << i;
    EXPECT_NEAR(sequence.entry(i).depth.stamp, expected[i].second, 1e-6) << "pair " << i;
  }
}

// --- The shared data's absence ----------------------------------------------------------------

void RequireAbsentFolder() { PLANEMAP_REQUIRE_SHARED("data/no_such_folder"); }

// A clone alone has no ../shared: a test that needs it is skipped with a message naming the missing
// folder; with PLANEMAP_REQUIRE_SHARED_DATA=1 (CI) the same is a failure.
TEST(SharedData, AMissingFolderIsNamedAndCiTurnsTheSkipIntoAFailure) {
  // The environment is restored at the end: the other tests read the real ../shared.
  const auto saved = [](const char* name) {
    const char* v = std::getenv(name);
    return v != nullptr ? std::optional<std::string>(v) : std::nullopt;
  };
  const std::optional<std::string> shared_before = saved("PLANEMAP_SHARED_DIR"), required_before = saved("PLANEMAP_REQUIRE_SHARED_DATA");
  const planemap::testing::TempDir shared;
  shared.Write("data/present/groundtruth.txt", "");
  ::setenv("PLANEMAP_SHARED_DIR", shared.path().c_str(), 1);
  EXPECT_EQ(planemap::testing::MissingShared("data/present"), "");
  const std::string missing = planemap::testing::MissingShared("data/no_such_folder");
  EXPECT_EQ(missing.rfind(shared.path() + "/data/no_such_folder missing", 0), 0u) << missing;
  ::setenv("PLANEMAP_REQUIRE_SHARED_DATA", "1", 1);
  EXPECT_TRUE(planemap::testing::SharedDataRequired());
  EXPECT_FATAL_FAILURE(RequireAbsentFolder(), "no_such_folder missing");
  ::setenv("PLANEMAP_REQUIRE_SHARED_DATA", "0", 1);
  EXPECT_FALSE(planemap::testing::SharedDataRequired());
  for (const auto& [name, value] : {std::pair{"PLANEMAP_SHARED_DIR", shared_before}, std::pair{"PLANEMAP_REQUIRE_SHARED_DATA", required_before}}) {
    if (value) {
      ::setenv(name, value->c_str(), 1);
    } else {
      ::unsetenv(name);
    }
  }
}

// --- Real TUM data -----------------------------------------------------------------------------

TEST(RealTum, Fr1XyzHasTwoFramesWithGroundTruth) {
  PLANEMAP_REQUIRE_SHARED("data/tum_frame_pairs/fr1_xyz");
  const std::string dir = SharedPath("data/tum_frame_pairs/fr1_xyz");
  const TumSequence sequence = TumSequence::Open(dir, OpenNiCamera());
  ASSERT_EQ(sequence.size(), 2u);
  EXPECT_TRUE(sequence.has_groundtruth());
  EXPECT_EQ(sequence.groundtruth().size(), 110u);  // PROVENANCE: cut to +-0.5 s around the frames
  EXPECT_FALSE(sequence.has_labels());
  ExpectAssociationsLikeAssociatePy(sequence, dir + "/associations.txt");
  EXPECT_NEAR(sequence.entry(0).depth.stamp, 1305031102.160407, 1e-6);
  EXPECT_NEAR(sequence.entry(1).color.stamp, 1305031102.275326, 1e-6);

  for (size_t i = 0; i < 2; ++i) {
    SCOPED_TRACE("frame " + std::to_string(i));
    ASSERT_TRUE(sequence.entry(i).T_world_camera.has_value());
    const RgbdFrame frame = sequence.LoadFrame(i);
    EXPECT_EQ(frame.index, static_cast<int>(i));
    EXPECT_NEAR(frame.stamp, sequence.entry(i).depth.stamp, 0.0);
    EXPECT_NEAR(frame.color_stamp, sequence.entry(i).color.stamp, 0.0);
    EXPECT_LT(std::abs(frame.stamp - frame.color_stamp), 0.02);  // associated within 20 ms
    ASSERT_TRUE(frame.T_world_camera.has_value());
    EXPECT_EQ(frame.depth.width(), 640);
    EXPECT_EQ(frame.depth.height(), 480);
    EXPECT_EQ(frame.color.width(), 640);
    EXPECT_EQ(frame.color.height(), 480);

    const DepthStats stats = Stats(frame.depth);
    // PROVENANCE: depth runs from about 0.86 m to 3.7 m in fr1_xyz.
    EXPECT_GT(stats.min, 0.75f);
    EXPECT_LT(stats.min, 1.0f);
    EXPECT_GT(stats.max, 3.0f);
    EXPECT_LT(stats.max, 4.0f);
    EXPECT_EQ(stats.invalid_nonzero, 0);
    // Measured: 0.748 and 0.752 of the pixels carry depth (Kinect v1 in an office); min 0.86-0.90 m,
    // max 3.60-3.72 m.
    EXPECT_GT(stats.valid_fraction, 0.65);
    EXPECT_LT(stats.valid_fraction, 0.85);
    // Depth comes in units of 1/5000 m.
    for (float z : frame.depth.pixels()) {
      if (z > 0.0f) {
        const double units = static_cast<double>(z) * 5000.0;
        ASSERT_NEAR(units, std::round(units), 1e-6 * units + 1e-3);
      }
    }
  }
  // The two frames are 0.1 s apart: the hand-held camera moves by centimetres and a few degrees.
  const Pose3& T0 = *sequence.entry(0).T_world_camera;
  const Pose3& T1 = *sequence.entry(1).T_world_camera;
  const double moved = planemap::testing::TranslationError(T0, T1);
  const double turned = planemap::testing::RotationErrorDeg(T0, T1);
  EXPECT_GT(moved, 1e-4);
  EXPECT_LT(moved, 0.05);  // [m]
  EXPECT_LT(turned, 3.0);  // [deg]
}

TEST(RealTum, Fr3FirstFrameHasNoGroundTruth) {
  PLANEMAP_REQUIRE_SHARED("data/tum_frame_pairs/fr3_long_office_household");
  const std::string dir = SharedPath("data/tum_frame_pairs/fr3_long_office_household");
  const TumSequence sequence =
      TumSequence::Open(dir, LoadCameraIntrinsics(SourcePath("configs/cameras/tum_fr3.yaml")));
  ASSERT_EQ(sequence.size(), 2u);
  ExpectAssociationsLikeAssociatePy(sequence, dir + "/associations.txt");
  EXPECT_EQ(sequence.groundtruth().size(), 271u);
  // Ground truth starts at 1341847980.7900, 67 ms after the first depth stamp: beyond the 20 ms gap.
  EXPECT_NEAR(sequence.groundtruth().front().stamp - sequence.entry(0).depth.stamp, 0.067, 0.001);
  EXPECT_FALSE(sequence.entry(0).T_world_camera.has_value());
  EXPECT_TRUE(sequence.entry(1).T_world_camera.has_value());
  // A wider gap (70 ms) lets the first frame take the first ground-truth pose.
  DatasetConfig wide;
  wide.max_groundtruth_gap = 0.07;
  const TumSequence wide_sequence = TumSequence::Open(dir, sequence.camera(), wide);
  ASSERT_TRUE(wide_sequence.entry(0).T_world_camera.has_value());
  EXPECT_TRUE(PosesNear(*wide_sequence.entry(0).T_world_camera, sequence.groundtruth().front().T_world_camera,
                        1e-9, 1e-12));

  const RgbdFrame first = sequence.LoadFrame(0);
  EXPECT_FALSE(first.T_world_camera.has_value());
  const RgbdFrame second = sequence.LoadFrame(1);
  ASSERT_TRUE(second.T_world_camera.has_value());
  for (const RgbdFrame* frame : {&first, &second}) {
    const DepthStats stats = Stats(frame->depth);
    // PROVENANCE: about 1.4-9.3 m over the two frames.
    EXPECT_GT(stats.min, 1.0f);
    EXPECT_LT(stats.max, 10.0f);
    EXPECT_EQ(stats.invalid_nonzero, 0);
    // Measured: 0.808 of the pixels carry depth in both frames; 1.45-9.33 m.
    EXPECT_GT(stats.valid_fraction, 0.75);
    EXPECT_LT(stats.valid_fraction, 0.99);
  }
}

TEST(RealTum, Fr1RpySliceHas100FramesAllWithGroundTruth) {
  PLANEMAP_REQUIRE_SHARED("data/tum_fr1_rpy_slice");
  const std::string dir = SharedPath("data/tum_fr1_rpy_slice");
  const TumSequence sequence = TumSequence::Open(dir, OpenNiCamera());
  ASSERT_EQ(sequence.size(), 100u);
  EXPECT_EQ(sequence.groundtruth().size(), 430u);
  ExpectAssociationsLikeAssociatePy(sequence, dir + "/associations.txt");
  for (size_t i = 0; i < sequence.size(); ++i) {
    EXPECT_TRUE(sequence.entry(i).T_world_camera.has_value()) << "frame " << i;
  }
  // The camera mostly rotates: about 1-4 deg between consecutive frames at 30 Hz (PROVENANCE).
  double max_step_deg = 0.0, total_deg = 0.0;
  for (size_t i = 1; i < sequence.size(); ++i) {
    const double step = planemap::testing::RotationErrorDeg(*sequence.entry(i - 1).T_world_camera,
                                                            *sequence.entry(i).T_world_camera);
    max_step_deg = std::max(max_step_deg, step);
    total_deg += step;
  }
  EXPECT_LT(max_step_deg, 8.0);
  EXPECT_GT(total_deg / (sequence.size() - 1), 0.5);
  // Every 11th frame: PROVENANCE says 72-80 % of the pixels have depth, in about 0.7-3.7 m.
  // Measured on these 10 frames: 0.724-0.808 valid, nearest 0.58 m (frame 99), farthest 3.80 m.
  for (size_t i = 0; i < sequence.size(); i += 11) {
    SCOPED_TRACE("frame " + std::to_string(i));
    const RgbdFrame frame = sequence.LoadFrame(i);
    const DepthStats stats = Stats(frame.depth);
    EXPECT_GT(stats.valid_fraction, 0.70);
    EXPECT_LT(stats.valid_fraction, 0.82);
    EXPECT_GT(stats.min, 0.5f);
    EXPECT_LT(stats.max, 4.0f);
    EXPECT_EQ(stats.invalid_nonzero, 0);
  }
}

// --- Write / read round trip -------------------------------------------------------------------

struct WrittenFrame {
  RgbdFrame frame;
  LabelImage labels;
};

// 80x60 camera so that PNG writing stays fast.
CameraIntrinsics SmallCamera(double depth_scale) {
  CameraIntrinsics camera = CameraIntrinsics{}.Scaled(0.125);
  camera.depth_scale = depth_scale;
  return camera;
}

std::vector<WrittenFrame> RandomFrames(const CameraIntrinsics& camera, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> depth_m(0.5f, 4.0f);
  std::uniform_real_distribution<double> coef(-1.0, 1.0), metres(-3.0, 3.0);
  std::uniform_int_distribution<int> byte(0, 255), label(0, 65535);
  std::bernoulli_distribution hole(0.1);
  std::vector<WrittenFrame> frames;
  for (int k = 0; k < count; ++k) {
    WrittenFrame w;
    w.frame.index = k;
    w.frame.stamp = 1305031102.160407 + k / 30.0;    // depth at 30 Hz [s]
    w.frame.color_stamp = w.frame.stamp + 0.011;     // colour 11 ms later [s]
    w.frame.depth = DepthImage(camera.width, camera.height);
    w.frame.color = ColorImage(camera.width, camera.height);
    w.labels = LabelImage(camera.width, camera.height);
    for (int v = 0; v < camera.height; ++v) {
      for (int u = 0; u < camera.width; ++u) {
        w.frame.depth.at(u, v) = hole(rng) ? 0.0f : depth_m(rng);
        w.frame.color.at(u, v) = {static_cast<std::uint8_t>(byte(rng)), static_cast<std::uint8_t>(byte(rng)),
                                  static_cast<std::uint8_t>(byte(rng))};
        w.labels.at(u, v) = static_cast<std::uint16_t>(label(rng));
      }
    }
    // Frame 2 has no ground truth (as if motion capture lost the camera).
    if (k != 2) {
      w.frame.T_world_camera = MakePose(Eigen::Quaterniond(coef(rng), coef(rng), coef(rng), coef(rng)),
                                        Eigen::Vector3d(metres(rng), metres(rng), metres(rng)));
    }
    frames.push_back(std::move(w));
  }
  return frames;
}

void WriteSequence(const std::string& dir, const CameraIntrinsics& camera, const std::vector<WrittenFrame>& frames,
                   bool with_labels) {
  TumSequenceWriter writer(dir, camera, with_labels);
  for (const WrittenFrame& w : frames) writer.Add(w.frame, with_labels ? &w.labels : nullptr);
  EXPECT_EQ(writer.frames_written(), frames.size());
}

class RoundTrip : public ::testing::TestWithParam<double> {};

TEST_P(RoundTrip, FramesReadBackAsWritten) {
  const double depth_scale = GetParam();  // units per metre
  const CameraIntrinsics camera = SmallCamera(depth_scale);
  const std::vector<WrittenFrame> written = RandomFrames(camera, 5, static_cast<unsigned>(depth_scale));
  TempDir tmp;
  const std::string dir = tmp.File("seq");
  WriteSequence(dir, camera, written, /*with_labels=*/true);

  const TumSequence sequence = TumSequence::Open(dir, camera);
  ASSERT_EQ(sequence.size(), written.size());
  EXPECT_TRUE(sequence.has_groundtruth());
  EXPECT_TRUE(sequence.has_labels());
  // Half a depth unit of rounding, plus float resolution at 4 m.
  const double depth_tolerance = 0.5 / depth_scale + 4.0 * std::numeric_limits<float>::epsilon();
  for (size_t i = 0; i < written.size(); ++i) {
    SCOPED_TRACE("frame " + std::to_string(i));
    const WrittenFrame& w = written[i];
    const RgbdFrame frame = sequence.LoadFrame(i);
    EXPECT_EQ(frame.index, static_cast<int>(i));
    EXPECT_NEAR(frame.stamp, w.frame.stamp, 1e-6);              // [s]
    EXPECT_NEAR(frame.color_stamp, w.frame.color_stamp, 1e-6);  // [s]
    EXPECT_TRUE(frame.color == w.frame.color);
    EXPECT_TRUE(sequence.LoadLabels(i) == w.labels);

    ASSERT_EQ(frame.depth.width(), w.frame.depth.width());
    ASSERT_EQ(frame.depth.height(), w.frame.depth.height());
    double max_error = 0.0;
    int zeros = 0;
    for (size_t p = 0; p < frame.depth.size(); ++p) {
      const float truth = w.frame.depth.pixels()[p], read = frame.depth.pixels()[p];
      if (truth == 0.0f) {
        ASSERT_EQ(read, 0.0f) << "pixel " << p;
        ++zeros;
      } else {
        max_error = std::max(max_error, std::abs(static_cast<double>(read) - truth));
      }
    }
    EXPECT_LE(max_error, depth_tolerance);        // [m]
    EXPECT_GT(max_error, 0.25 / depth_scale);     // the depth really was quantised
    EXPECT_GT(zeros, 0);

    ASSERT_EQ(frame.T_world_camera.has_value(), w.frame.T_world_camera.has_value());
    ASSERT_EQ(sequence.entry(i).T_world_camera.has_value(), w.frame.T_world_camera.has_value());
    if (w.frame.T_world_camera) {
      EXPECT_TRUE(PosesNear(*frame.T_world_camera, *w.frame.T_world_camera, 1e-6 * kRadToDeg, 1e-6));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(DepthScales, RoundTrip, ::testing::Values(5000.0, 1000.0),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return "Scale" + std::to_string(static_cast<int>(info.param));
                         });

TEST(DepthPng, DepthBeyondSixteenBitsBecomesNoData) {
  // 15 m is 75000 units at 5000/m (does not fit 16 bits, so no data) but 15000 units at 1000/m.
  for (double depth_scale : {5000.0, 1000.0}) {
    SCOPED_TRACE("depth_scale " + std::to_string(depth_scale));
    const CameraIntrinsics camera = SmallCamera(depth_scale);
    std::vector<WrittenFrame> frames = RandomFrames(camera, 1, 3);
    frames[0].frame.depth.at(10, 10) = 15.0f;
    frames[0].frame.depth.at(11, 10) = std::numeric_limits<float>::quiet_NaN();
    frames[0].frame.depth.at(12, 10) = -1.0f;
    TempDir tmp;
    WriteSequence(tmp.File("seq"), camera, frames, false);
    const TumSequence sequence = TumSequence::Open(tmp.File("seq"), camera);
    EXPECT_FALSE(sequence.has_labels());
    const RgbdFrame frame = sequence.LoadFrame(0);
    if (depth_scale == 5000.0) {
      EXPECT_EQ(frame.depth.at(10, 10), 0.0f);
    } else {
      EXPECT_NEAR(frame.depth.at(10, 10), 15.0, 0.5 / depth_scale);
    }
    EXPECT_EQ(frame.depth.at(11, 10), 0.0f);  // NaN: no data
    EXPECT_EQ(frame.depth.at(12, 10), 0.0f);  // negative: no data
  }
}

// --- Bad input ---------------------------------------------------------------------------------

// A valid 3-frame sequence (80x60, no labels) in tmp/seq.
std::string GoodSequence(const TempDir& tmp, const CameraIntrinsics& camera) {
  const std::string dir = tmp.File("seq");
  WriteSequence(dir, camera, RandomFrames(camera, 3, 99), false);
  return dir;
}

TEST(BadInput, MissingSequenceFolder) {
  TempDir tmp;
  const std::string dir = tmp.File("no_such_sequence");
  EXPECT_THROW(TumSequence::Open(dir, OpenNiCamera()), InputError);
  EXPECT_TRUE(ThrowsWith([&] { TumSequence::Open(dir, OpenNiCamera()); }, {dir, "does not exist"}));
}

TEST(BadInput, FolderWithoutRgbList) {
  TempDir tmp;
  const CameraIntrinsics camera = SmallCamera(5000.0);
  const std::string dir = GoodSequence(tmp, camera);
  fs::remove(dir + "/rgb.txt");
  EXPECT_THROW(TumSequence::Open(dir, camera), InputError);
  EXPECT_TRUE(ThrowsWith([&] { TumSequence::Open(dir, camera); }, {"rgb.txt", "cannot open"}));
}

TEST(BadInput, MalformedLineInDepthList) {
  TempDir tmp;
  const CameraIntrinsics camera = SmallCamera(5000.0);
  const std::string dir = GoodSequence(tmp, camera);
  tmp.Write("seq/depth.txt",
            "# depth maps\n"
            "1305031102.160407 depth/1305031102.160407.png\n"
            "1305031102.193740depth/1305031102.193740.png\n");
  EXPECT_THROW(TumSequence::Open(dir, camera), InputError);
  EXPECT_TRUE(ThrowsWith([&] { TumSequence::Open(dir, camera); }, {dir + "/depth.txt:3:"}));
}

TEST(BadInput, ListRefersToAMissingImage) {
  TempDir tmp;
  const CameraIntrinsics camera = SmallCamera(5000.0);
  const std::string dir = GoodSequence(tmp, camera);
  const TumSequence sequence = TumSequence::Open(dir, camera);
  ASSERT_EQ(sequence.size(), 3u);
  // Frame 1 is on line 5 of depth.txt (3 header lines); its image disappears after Open.
  ASSERT_EQ(sequence.entry(1).depth.line, 5);
  const std::string image = dir + "/" + sequence.entry(1).depth.path;
  ASSERT_TRUE(fs::remove(image));
  EXPECT_NO_THROW(sequence.LoadFrame(0));
  EXPECT_THROW(sequence.LoadFrame(1), InputError);
  EXPECT_TRUE(ThrowsWith([&] { sequence.LoadFrame(1); }, {image, "depth.txt:5"}));

  // The same for a colour image: rgb.txt names it.
  const std::string color = dir + "/" + sequence.entry(2).color.path;
  ASSERT_TRUE(fs::remove(color));
  EXPECT_TRUE(ThrowsWith([&] { sequence.LoadFrame(2); }, {color, "rgb.txt:6"}));
}

TEST(BadInput, EightBitDepthPng) {
  TempDir tmp;
  const CameraIntrinsics camera = SmallCamera(5000.0);
  const std::string dir = GoodSequence(tmp, camera);
  const TumSequence sequence = TumSequence::Open(dir, camera);
  const std::string image = dir + "/" + sequence.entry(0).depth.path;
  // An 8-bit depth image as produced by a careless conversion (values in decimetres).
  cv::Mat eight_bit(camera.height, camera.width, CV_8UC1, cv::Scalar(20));
  ASSERT_TRUE(cv::imwrite(image, eight_bit));
  EXPECT_THROW(sequence.LoadFrame(0), InputError);
  EXPECT_TRUE(ThrowsWith([&] { sequence.LoadFrame(0); }, {image, "depth.txt:4", "8 bits"}));
}

TEST(BadInput, ImageSizeDiffersFromCamera) {
  TempDir tmp;
  const CameraIntrinsics small = SmallCamera(5000.0);  // 80x60 images on disk
  const std::string dir = GoodSequence(tmp, small);
  // Without the camera.yaml planemap writes (as for sequences from elsewhere), the images
  // themselves must reveal the mismatch.
  std::filesystem::remove(dir + "/camera.yaml");
  const TumSequence sequence = TumSequence::Open(dir, OpenNiCamera());  // expects 640x480
  const std::string image = dir + "/" + sequence.entry(0).depth.path;
  EXPECT_THROW(sequence.LoadFrame(0), InputError);
  EXPECT_TRUE(ThrowsWith([&] { sequence.LoadFrame(0); }, {image, "depth.txt:4", "80x60", "640x480"}));
}

TEST(BadInput, CameraOtherThanTheOneTheSequenceWasWrittenWith) {
  TempDir tmp;
  const std::string dir = GoodSequence(tmp, SmallCamera(1000.0));
  CameraIntrinsics other_scale = SmallCamera(1000.0);
  other_scale.depth_scale = 5000.0;
  EXPECT_TRUE(ThrowsWith([&] { TumSequence::Open(dir, other_scale); },
                         {dir + "/camera.yaml", "another camera", "depth_scale 1000"}));
  ASSERT_TRUE(TumSequence::StoredCamera(dir).has_value());
  EXPECT_EQ(TumSequence::StoredCamera(dir)->depth_scale, 1000.0);
  EXPECT_NO_THROW(TumSequence::Open(dir, *TumSequence::StoredCamera(dir)));
}

TEST(BadInput, NoColourDepthPairWithinTheGap) {
  TempDir tmp;
  const std::string dir = tmp.File("seq");
  // Colour and depth alternate 50 ms apart: nothing within 20 ms.
  tmp.Write("seq/rgb.txt", "100.00 rgb/100.00.png\n100.10 rgb/100.10.png\n");
  tmp.Write("seq/depth.txt", "100.05 depth/100.05.png\n100.15 depth/100.15.png\n");
  EXPECT_THROW(TumSequence::Open(dir, OpenNiCamera()), InputError);
  EXPECT_TRUE(ThrowsWith([&] { TumSequence::Open(dir, OpenNiCamera()); }, {dir + "/depth.txt", "no depth image"}));
  // A 60 ms gap pairs them.
  DatasetConfig wide;
  wide.max_association_gap = 0.06;
  EXPECT_EQ(TumSequence::Open(dir, OpenNiCamera(), wide).size(), 2u);
}

TEST(BadInput, InvalidCameraIsRejected) {
  PLANEMAP_REQUIRE_SHARED("data/tum_frame_pairs/fr1_xyz");
  const std::string dir = SharedPath("data/tum_frame_pairs/fr1_xyz");
  CameraIntrinsics nan_fx = OpenNiCamera();
  nan_fx.fx = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(TumSequence::Open(dir, nan_fx), std::invalid_argument);
  EXPECT_TRUE(ThrowsWith([&] { TumSequence::Open(dir, nan_fx); }, {"camera.fx", "finite"}));

  CameraIntrinsics negative_fx = OpenNiCamera();
  negative_fx.fx = -525.0;
  EXPECT_THROW(TumSequence::Open(dir, negative_fx), std::invalid_argument);
  EXPECT_TRUE(ThrowsWith([&] { TumSequence::Open(dir, negative_fx); }, {"camera.fx", "> 0"}));
}

}  // namespace
}  // namespace planemap
