// bench_real's rules (which sequences, which camera, which frames, which error), the planemap
// tool's outputs as it reads them, and the OpenCV peers on real frames against ground truth.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "opencv_odometry.h"
#include "planemap_run.h"
#include "real_table.h"
#include "test_support.h"

namespace planemap {
namespace {

namespace fs = std::filesystem;
using testing::SharedPath;
using testing::SourcePath;
using testing::TempDir;

constexpr double kDegToRad = M_PI / 180.0;

TEST(RealTable, CameraByTheTumAndIclNamingConvention) {
  EXPECT_EQ(CameraFileByName("tum_fr1_rpy_slice"), "configs/cameras/tum_fr1.yaml");
  EXPECT_EQ(CameraFileByName("tum_frame_pairs/fr1_xyz"), "configs/cameras/tum_fr1.yaml");
  EXPECT_EQ(CameraFileByName("rgbd_dataset_freiburg2_desk"), "configs/cameras/tum_fr2.yaml");
  EXPECT_EQ(CameraFileByName("held_out/FR3_cabinet"), "configs/cameras/tum_fr3.yaml");
  EXPECT_EQ(CameraFileByName("icl_living_room_kt1"), "configs/cameras/icl_nuim.yaml");
  EXPECT_EQ(CameraFileByName("kitchen"), std::nullopt);
}

TEST(RealTable, StridesKeepTheFramesPlanemapMapUses) {
  EXPECT_EQ(StridedFrames(100, 20), (std::vector<size_t>{0, 20, 40, 60, 80}));
  EXPECT_EQ(StridedFrames(101, 20).size(), 6u);
  EXPECT_EQ(StridedFrames(2, 1), (std::vector<size_t>{0, 1}));
  EXPECT_EQ(StridedFrames(2, 5), (std::vector<size_t>{0}));  // a pair at stride 5 is skipped
}

TEST(RealTable, RpeOverOneSecondOrWholeFrameSteps) {
  const double frame = 1.0 / 30.0;  // [s]
  for (const int stride : {1, 5, 10}) {
    const RpeChoice rpe = ChooseRpeDelta(stride * frame);
    EXPECT_TRUE(rpe.one_second) << "stride " << stride;
    EXPECT_DOUBLE_EQ(rpe.delta, 1.0);
    EXPECT_DOUBLE_EQ(rpe.tolerance, 0.5 * stride * frame);
  }
  // TUM's fr3 frames, 32.7 ms apart: 31 steps are 1.014 s, within 5 % of a second.
  EXPECT_TRUE(ChooseRpeDelta(0.0327).one_second);
  // 0.45 s apart: 2 steps are 0.9 s, not within 5 %: the RPE is over 0.9 s and says so.
  EXPECT_FALSE(ChooseRpeDelta(0.45).one_second);
  EXPECT_NEAR(ChooseRpeDelta(0.45).delta, 0.9, 1e-12);
  // 0.67 s apart: 1 s is 1.5 steps; the delta is one step, and the table says so.
  const RpeChoice stride20 = ChooseRpeDelta(20 * frame);
  EXPECT_FALSE(stride20.one_second);
  EXPECT_EQ(stride20.steps, 1);
  EXPECT_NEAR(stride20.delta, 0.667, 1e-3);
  // 2.3 s apart (the fr3 pair): one step.
  EXPECT_NEAR(ChooseRpeDelta(2.3).delta, 2.3, 1e-12);
  // Five frames 0.1 s apart span less than 1 s: one step, not a delta no pair has.
  const RpeChoice short_run = ChooseRpeDelta(std::vector<double>{0.0, 0.1, 0.2, 0.3, 0.4});
  EXPECT_TRUE(short_run.no_pair_within);
  EXPECT_NEAR(short_run.delta, 0.1, 1e-12);
}

TEST(RealTable, TwoFramesPairWithAGroundTruthThatStartsJustAfterTheFirst) {
  Trajectory truth;
  for (int k = 0; k <= 100; ++k) truth.push_back({10.067 + 0.01 * k, Pose3::Identity()});  // 10.067-11.067 s
  // Within 20 ms only the second frame pairs; within 0.1 s both, 67 ms off at most.
  const GroundTruthPairing pair = PairWithGroundTruth(truth, {10.0, 11.0}, 0.02);
  EXPECT_TRUE(pair.widened);
  EXPECT_EQ(pair.frames, 2u);
  EXPECT_NEAR(pair.largest_offset, 0.067, 1e-9);
  // Three frames keep the 20 ms rule (their two with ground truth give the pair error).
  const GroundTruthPairing run = PairWithGroundTruth(truth, {10.0, 10.5, 11.0}, 0.02);
  EXPECT_FALSE(run.widened);
  EXPECT_EQ(run.frames, 2u);
}

TEST(RealTable, PairErrorIsTheRelativeMotionsDifference) {
  const Pose3 first = MakePoseRpy(0.1, -0.2, 0.3, {1.0, 2.0, 0.5});
  const Pose3 motion = MakePoseRpy(0.0, 0.05, 0.02, {0.10, 0.0, 0.02});
  const Pose3 last = first * motion;
  // The estimate in another world (frame-to-frame methods start anywhere): no error.
  const Pose3 T_other_world = MakePoseRpy(0.5, 0.0, -1.0, {3.0, -1.0, 0.0});
  const PairError none = RelativePoseError(first, last, T_other_world * first, T_other_world * last);
  EXPECT_NEAR(none.translation, 0.0, 1e-12);
  EXPECT_NEAR(none.rotation_deg, 0.0, 1e-6);
  // The last pose turned by 2 deg about its z, or moved 1 cm along the first camera's x.
  const Pose3 turned = last * MakePoseRpy(0.0, 0.0, 2.0 * kDegToRad, Eigen::Vector3d::Zero());
  EXPECT_NEAR(RelativePoseError(first, last, first, turned).rotation_deg, 2.0, 1e-9);
  Pose3 moved = last;
  moved.translation() += first.linear() * Eigen::Vector3d(0.01, 0.0, 0.0);
  EXPECT_NEAR(RelativePoseError(first, last, first, moved).translation, 0.01, 1e-12);
}

void WriteSequenceLists(const fs::path& dir, bool with_groundtruth) {
  fs::create_directories(dir);
  std::ofstream(dir / "rgb.txt") << "0.0 rgb/0.png\n";
  std::ofstream(dir / "depth.txt") << "0.0 depth/0.png\n";
  if (with_groundtruth) std::ofstream(dir / "groundtruth.txt") << "0.0 0 0 0 0 0 0 1\n";
}

TEST(RealTable, FindsSequencesWithGroundTruthInSubfolders) {
  TempDir data;
  WriteSequenceLists(fs::path(data.path()) / "tum_fr1_a", true);
  WriteSequenceLists(fs::path(data.path()) / "pairs" / "fr3_b", true);
  WriteSequenceLists(fs::path(data.path()) / "no_truth", false);
  fs::create_directories(fs::path(data.path()) / "icl_c");
  std::ofstream(fs::path(data.path()) / "icl_c" / "associations.txt") << "0.0 rgb/0.png 0.0 depth/0.png\n";
  std::ofstream(fs::path(data.path()) / "icl_c" / "groundtruth.txt") << "0.0 0 0 0 0 0 0 1\n";
  const std::vector<RealSequence> found = FindRealSequences(data.path());
  ASSERT_EQ(found.size(), 3u);
  EXPECT_EQ(found[0].name, "icl_c");
  EXPECT_EQ(found[1].name, "pairs/fr3_b");
  EXPECT_EQ(found[2].name, "tum_fr1_a");
  // By relative path or by folder name; an unknown name lists the ones there are.
  EXPECT_EQ(SelectSequences(found, {"fr3_b"}).front().name, "pairs/fr3_b");
  EXPECT_EQ(SelectSequences(found, {"pairs/fr3_b", "tum_fr1_a"}).size(), 2u);
  EXPECT_TRUE(testing::ThrowsWith([&] { SelectSequences(found, {"no_truth"}); },
                                  {"no_truth", "found: icl_c, pairs/fr3_b"}));
  // --data pointing at one sequence: that sequence, named by its folder.
  const std::vector<RealSequence> one =
      FindRealSequences((fs::path(data.path()) / "pairs" / "fr3_b").string());
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].name, "fr3_b");
}

TEST(RealTable, ReadsTrackingCsvAndTheBatchTime) {
  TempDir dir;
  const std::string csv = dir.Write(
      "tracking.csv",
      "frame,stamp,status,planes,matched,inliers,added,refined,frontend_ms,tracking_ms,window_ms,reason\n"
      "0,1.000000,tracked,5,0,0,5,0,4.5,1.25,0.5,\n"
      "5,1.166667,degraded,2,2,2,0,1,4,1,0.75,two planes; one direction predicted\n");
  const std::vector<TrackingLogRow> rows = ReadTrackingLog(csv);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].status, "degraded");
  EXPECT_DOUBLE_EQ(rows[0].frontend_ms + rows[0].tracking_ms + rows[0].window_ms, 6.25);
  const std::string old = dir.Write("old.csv", "frame,stamp,status,frontend_ms,tracking_ms,reason\n");
  EXPECT_TRUE(testing::ThrowsWith([&] { ReadTrackingLog(old); }, {"old.csv:1", "window_ms"}));
  const std::string out =
      "refine: 20 poses, 30 planes, 1 boxes, 400 residual blocks (300 plane observations, 2 dropped as "
      "outliers)\n"
      "refine: SPARSE_NORMAL_CHOLESKY (SUITE_SPARSE), 12 iterations, 0.412 s (34.33 ms per iteration), cost "
      "10 -> 1, "
      "CONVERGENCE; covariances 0.100 s\n";
  EXPECT_DOUBLE_EQ(RefineSeconds(out).value_or(-1.0), 0.412);
  EXPECT_FALSE(RefineSeconds("frames 20: tracked 20").has_value());
}

// OpenCV's compute(src, dst, Rt) gives dst_p = Rt * src_p; composed the other way round, the pair's
// 3.8 cm of motion comes out reversed (7.4 cm off). RgbdICPOdometry, default parameters, on the
// fr1_xyz pair (0.1 s apart) must recover the true relative motion within 2 cm and 2 deg.
TEST(RealTable, RgbdIcpOdometryRecoversTheFr1XyzMotion) {
  const std::string dir = SharedPath("data/tum_frame_pairs/fr1_xyz");
  PLANEMAP_REQUIRE_SHARED("data/tum_frame_pairs/fr1_xyz");
  const TumSequence sequence =
      TumSequence::Open(dir, LoadCameraIntrinsics(SourcePath(*CameraFileByName("fr1_xyz"))));
  ASSERT_EQ(sequence.size(), 2u);
  ASSERT_TRUE(sequence.entry(0).T_world_camera && sequence.entry(1).T_world_camera);
  const OdometryRun run =
      RunOpenCvOdometry("RgbdICPOdometry", sequence, {0, 1}, *sequence.entry(0).T_world_camera);
  ASSERT_TRUE(run.error.empty()) << run.error;
  ASSERT_EQ(run.trajectory.size(), 2u);
  EXPECT_EQ(run.failures, 0);
  const PairError error =
      RelativePoseError(*sequence.entry(0).T_world_camera, *sequence.entry(1).T_world_camera,
                        run.trajectory[0].T_world_camera, run.trajectory[1].T_world_camera);
  std::printf("fr1_xyz pair, RgbdICPOdometry: %.2f cm, %.2f deg from the true relative motion\n",
              100 * error.translation, error.rotation_deg);
  EXPECT_LT(error.translation, 0.02) << "m";
  EXPECT_LT(error.rotation_deg, 2.0);
}

}  // namespace
}  // namespace planemap
