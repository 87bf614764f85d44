// TUM RGB-D text formats: file lists, trajectories, stamp association and pose look-up.
#include <algorithm>
#include <ostream>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "planemap/core/error.h"
#include "planemap/core/tum_format.h"
#include "test_support.h"

namespace planemap {
namespace {

using planemap::testing::PosesNear;
using planemap::testing::RotationErrorDeg;
using planemap::testing::TempDir;
using planemap::testing::ThrowsWith;
using planemap::testing::TranslationError;

constexpr double kDeg = M_PI / 180.0;

// --- File lists --------------------------------------------------------------------------------

TEST(ReadFileList, SkipsCommentsAndBlankLines) {
  TempDir dir;
  const std::string file = dir.Write("rgb.txt",
                                     "# color images\n"
                                     "# file: 'rgbd_dataset_freiburg1_xyz.bag'\n"
                                     "\n"
                                     "1305031102.175304 rgb/1305031102.175304.png\n"
                                     "   # an indented comment\n"
                                     "1305031102.211214 rgb/1305031102.211214.png   \n"
                                     "   \t\n"
                                     "\t1305031102.275326\trgb/1305031102.275326.png\n");
  const std::vector<StampedFile> entries = ReadFileList(file);
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_NEAR(entries[0].stamp, 1305031102.175304, 1e-6);  // [s]
  EXPECT_NEAR(entries[1].stamp, 1305031102.211214, 1e-6);
  EXPECT_NEAR(entries[2].stamp, 1305031102.275326, 1e-6);
  EXPECT_EQ(entries[0].path, "rgb/1305031102.175304.png");
  EXPECT_EQ(entries[1].path, "rgb/1305031102.211214.png");
  EXPECT_EQ(entries[2].path, "rgb/1305031102.275326.png");
  EXPECT_EQ(entries[0].line, 4);
  EXPECT_EQ(entries[1].line, 6);
  EXPECT_EQ(entries[2].line, 8);
}

TEST(ReadFileList, EqualStampsAreAllowed) {
  TempDir dir;
  const std::string file = dir.Write("depth.txt", "1.5 depth/a.png\n1.5 depth/b.png\n");
  const std::vector<StampedFile> entries = ReadFileList(file);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].stamp, entries[1].stamp);
}

TEST(ReadFileList, OnlyCommentsGiveAnEmptyList) {
  TempDir dir;
  EXPECT_TRUE(ReadFileList(dir.Write("rgb.txt", "# color images\n\n# timestamp filename\n")).empty());
}

struct MalformedList {
  const char* name;
  const char* content;
  int bad_line;
};

void PrintTo(const MalformedList& list, std::ostream* os) { *os << list.name; }

class ReadFileListMalformed : public ::testing::TestWithParam<MalformedList> {};

TEST_P(ReadFileListMalformed, ThrowsNamingFileAndLine) {
  TempDir dir;
  const std::string file = dir.Write("depth.txt", GetParam().content);
  EXPECT_THROW(ReadFileList(file), InputError);
  EXPECT_TRUE(ThrowsWith([&] { ReadFileList(file); }, {file + ":" + std::to_string(GetParam().bad_line) + ":"}));
}

INSTANTIATE_TEST_SUITE_P(
    Lines, ReadFileListMalformed,
    ::testing::Values(
        MalformedList{"OneToken", "# depth maps\n1.0 depth/1.png\n2.0\n", 3},
        MalformedList{"ThreeTokens", "# depth maps\n1.0 depth/1.png\n\n2.0 depth/2.png extra\n", 4},
        MalformedList{"NonNumericStamp", "# depth maps\nabc depth/1.png\n", 2},
        MalformedList{"StampWithTrailingJunk", "1.0 depth/1.png\n2.0s depth/2.png\n", 2},
        MalformedList{"NanStamp", "1.0 depth/1.png\nnan depth/2.png\n", 2},
        MalformedList{"InfiniteStamp", "inf depth/1.png\n", 1},
        MalformedList{"StampGoesBackwards", "# depth maps\n1.0 depth/1.png\n2.0 depth/2.png\n1.5 depth/3.png\n", 4}),
    [](const ::testing::TestParamInfo<MalformedList>& info) { return std::string(info.param.name); });

TEST(ReadFileList, MissingFileNamesIt) {
  TempDir dir;
  const std::string file = dir.File("rgb.txt");
  EXPECT_THROW(ReadFileList(file), InputError);
  EXPECT_TRUE(ThrowsWith([&] { ReadFileList(file); }, {file}));
}

TEST(WriteFileList, RoundTrip) {
  TempDir dir;
  const std::vector<StampedFile> written = {{1305031102.160407, "depth/1305031102.160407.png", 0},
                                            {1305031102.262886, "depth/1305031102.262886.png", 0}};
  const std::string file = dir.File("depth.txt");
  WriteFileList(file, "# depth maps\n# timestamp filename\n", written);
  const std::vector<StampedFile> read = ReadFileList(file);
  ASSERT_EQ(read.size(), 2u);
  for (size_t i = 0; i < read.size(); ++i) {
    EXPECT_NEAR(read[i].stamp, written[i].stamp, 1e-6);
    EXPECT_EQ(read[i].path, written[i].path);
    EXPECT_EQ(read[i].line, static_cast<int>(i) + 3);
  }
}

// --- Trajectories ------------------------------------------------------------------------------

TEST(TumTrajectory, WriteThenReadIsEqual) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> coef(-1.0, 1.0), metres(-10.0, 10.0), step(0.005, 0.05);
  Trajectory written;
  double stamp = 1305031102.175304;
  for (int k = 0; k < 200; ++k) {
    stamp += step(rng);
    const Eigen::Quaterniond q(coef(rng), coef(rng), coef(rng), coef(rng));
    written.push_back({stamp, MakePose(q, Eigen::Vector3d(metres(rng), metres(rng), metres(rng)))});
  }
  TempDir dir;
  const std::string file = dir.File("groundtruth.txt");
  WriteTumTrajectory(file, written);
  const Trajectory read = ReadTumTrajectory(file);
  ASSERT_EQ(read.size(), written.size());
  for (size_t i = 0; i < read.size(); ++i) {
    EXPECT_NEAR(read[i].stamp, written[i].stamp, 1e-6);  // [s]
    EXPECT_LE(TranslationError(read[i].T_world_camera, written[i].T_world_camera), 1e-6);      // [m]
    EXPECT_LE(RotationErrorDeg(read[i].T_world_camera, written[i].T_world_camera) * kDeg, 1e-6);  // [rad]
  }
}

TEST(TumTrajectory, ReadsTheTumLayout) {
  TempDir dir;
  // Two lines of the fr3/long_office_household ground truth.
  const std::string file = dir.Write("groundtruth.txt",
                                     "# ground truth trajectory\n"
                                     "# timestamp tx ty tz qx qy qz qw\n"
                                     "1341847980.7900 -0.6832 2.6909 1.7373 0.0003 0.8617 -0.5072 -0.0145\n"
                                     "1341847980.8000 -0.6829 2.6910 1.7373 0.0002 0.8613 -0.5078 -0.0146\n");
  const Trajectory trajectory = ReadTumTrajectory(file);
  ASSERT_EQ(trajectory.size(), 2u);
  EXPECT_NEAR(trajectory[0].stamp, 1341847980.79, 1e-6);
  EXPECT_NEAR((trajectory[0].T_world_camera.translation() - Eigen::Vector3d(-0.6832, 2.6909, 1.7373)).norm(),
              0.0, 1e-12);
  // The 4-decimal quaternion is not exactly unit; it is normalised on reading.
  const Eigen::Matrix3d R = trajectory[0].T_world_camera.linear();
  EXPECT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
  const Eigen::Quaterniond expected = Eigen::Quaterniond(-0.0145, 0.0003, 0.8617, -0.5072).normalized();
  EXPECT_NEAR(Eigen::Quaterniond(R).angularDistance(expected), 0.0, 1e-9);
  // 10 ms between the two poses moves the camera 0.3 mm.
  EXPECT_NEAR(TranslationError(trajectory[0].T_world_camera, trajectory[1].T_world_camera), 3.1623e-4, 1e-7);
}

TEST(TumTrajectory, RejectsANonUnitQuaternion) {
  TempDir dir;
  const std::string file = dir.Write("groundtruth.txt",
                                     "# timestamp tx ty tz qx qy qz qw\n"
                                     "1.00 0 0 0 0 0 0 1\n"
                                     "1.01 0 0 0 0 0 0 2\n");
  EXPECT_THROW(ReadTumTrajectory(file), InputError);
  EXPECT_TRUE(ThrowsWith([&] { ReadTumTrajectory(file); }, {file + ":3:", "quaternion"}));
}

TEST(TumTrajectory, AcceptsAQuaternionWithinTolerance) {
  TempDir dir;
  const std::string file = dir.Write("groundtruth.txt", "1.00 0 0 0 0 0 0 1.0005\n");
  const Trajectory trajectory = ReadTumTrajectory(file);
  ASSERT_EQ(trajectory.size(), 1u);
  EXPECT_NEAR(RotationAngle(trajectory[0].T_world_camera.linear()), 0.0, 1e-15);
  EXPECT_NEAR(trajectory[0].T_world_camera.linear().determinant(), 1.0, 1e-15);
}

TEST(TumTrajectory, RejectsASevenNumberLine) {
  TempDir dir;
  const std::string file = dir.Write("groundtruth.txt",
                                     "# timestamp tx ty tz qx qy qz qw\n"
                                     "\n"
                                     "1.00 0 0 0 0 0 0 1\n"
                                     "1.01 0 0 0 0 0 1\n");
  EXPECT_THROW(ReadTumTrajectory(file), InputError);
  EXPECT_TRUE(ThrowsWith([&] { ReadTumTrajectory(file); }, {file + ":4:"}));
}

TEST(TumTrajectory, RejectsNonNumericAndBackwardsLines) {
  TempDir dir;
  const std::string nan_file = dir.Write("nan.txt", "1.00 0 0 nan 0 0 0 1\n");
  EXPECT_TRUE(ThrowsWith([&] { ReadTumTrajectory(nan_file); }, {nan_file + ":1:"}));
  const std::string back = dir.Write("back.txt", "1.00 0 0 0 0 0 0 1\n0.99 0 0 0 0 0 0 1\n");
  EXPECT_TRUE(ThrowsWith([&] { ReadTumTrajectory(back); }, {back + ":2:", "back in time"}));
}

// --- Association -------------------------------------------------------------------------------

using Pairs = std::vector<std::pair<size_t, size_t>>;

// Stamps in exact binary fractions of a second (1/128 s), so gaps compare exactly.
std::vector<double> Stamps(std::initializer_list<int> ticks) {
  std::vector<double> stamps;
  for (int t : ticks) stamps.push_back(1000.0 + t / 128.0);
  return stamps;
}

TEST(AssociateStamps, GreedyBySmallestGapNotNearestPerStamp) {
  // a0-b0 gap 2, a1-b0 gap 1, a1-b1 gap 2, a0-b1 gap 5 (ticks of 1/128 s), max gap 4 ticks.
  // Greedy takes a1-b0 first; a0 and b1 then have no partner closer than 4 ticks.
  const Pairs pairs = AssociateStamps(Stamps({0, 3}), Stamps({2, 5}), 4 / 128.0);
  EXPECT_EQ(pairs, (Pairs{{1, 0}}));
}

TEST(AssociateStamps, HandMadeExampleLikeAssociatePy) {
  const std::vector<double> a = Stamps({0, 10, 20, 30, 40});
  const std::vector<double> b = Stamps({1, 8, 12, 27, 44, 60});
  // Gaps below 4 ticks: a0-b0 1, a1-b1 2, a1-b2 2 (tie, the earlier b wins), a3-b3 3.
  // a4-b4 is exactly 4 ticks: associate.py keeps only gaps < max_difference, so it is dropped.
  const Pairs pairs = AssociateStamps(a, b, 4 / 128.0);
  EXPECT_EQ(pairs, (Pairs{{0, 0}, {1, 1}, {3, 3}}));
  // With a larger gap a4-b4 joins, and a2 takes b2 (8 ticks < 9).
  EXPECT_EQ(AssociateStamps(a, b, 9 / 128.0), (Pairs{{0, 0}, {1, 1}, {2, 2}, {3, 3}, {4, 4}}));
}

TEST(AssociateStamps, EmptyInputs) {
  EXPECT_TRUE(AssociateStamps({}, Stamps({0, 1}), 0.02).empty());
  EXPECT_TRUE(AssociateStamps(Stamps({0, 1}), {}, 0.02).empty());
}

// Straight port of TUM's associate.py (offset 0): all pairs with |a - b| < max_difference,
// sorted by (gap, a, b), taken greedily.
Pairs AssociatePy(const std::vector<double>& a, const std::vector<double>& b, double max_difference) {
  std::vector<std::tuple<double, double, double, size_t, size_t>> potential;
  for (size_t i = 0; i < a.size(); ++i) {
    for (size_t j = 0; j < b.size(); ++j) {
      const double diff = std::abs(a[i] - b[j]);
      if (diff < max_difference) potential.emplace_back(diff, a[i], b[j], i, j);
    }
  }
  std::sort(potential.begin(), potential.end());
  std::vector<bool> a_free(a.size(), true), b_free(b.size(), true);
  Pairs matches;
  for (const auto& [diff, sa, sb, i, j] : potential) {
    if (a_free[i] && b_free[j]) {
      a_free[i] = b_free[j] = false;
      matches.emplace_back(i, j);
    }
  }
  std::sort(matches.begin(), matches.end());
  return matches;
}

TEST(AssociateStamps, MatchesAssociatePyOnKinectLikeStreams) {
  std::mt19937 rng(1234);
  std::uniform_real_distribution<double> jitter(-0.004, 0.004), offset(-0.03, 0.03);
  std::bernoulli_distribution dropped(0.1);
  for (int trial = 0; trial < 20; ++trial) {
    // Colour and depth at ~30 Hz with jitter, dropped frames and a relative offset [s].
    std::vector<double> depth, rgb;
    const double t0 = 1305031102.0, shift = offset(rng);
    for (int k = 0; k < 120; ++k) {
      if (!dropped(rng)) depth.push_back(t0 + k / 30.0 + jitter(rng));
      if (!dropped(rng)) rgb.push_back(t0 + shift + k / 30.0 + jitter(rng));
    }
    std::sort(depth.begin(), depth.end());
    std::sort(rgb.begin(), rgb.end());
    const Pairs pairs = AssociateStamps(depth, rgb, 0.02);
    EXPECT_EQ(pairs, AssociatePy(depth, rgb, 0.02)) << "trial " << trial;
    // Each stamp is used at most once and every pair is closer than the gap.
    std::vector<int> a_uses(depth.size(), 0), b_uses(rgb.size(), 0);
    for (const auto& [i, j] : pairs) {
      EXPECT_LT(std::abs(depth[i] - rgb[j]), 0.02);
      ++a_uses[i];
      ++b_uses[j];
    }
    EXPECT_LE(*std::max_element(a_uses.begin(), a_uses.end()), 1);
    EXPECT_LE(*std::max_element(b_uses.begin(), b_uses.end()), 1);
    EXPECT_GT(pairs.size(), 60u);  // most frames find a partner
  }
}

TEST(AssociateStamps, UnsortedSecondListMatchesAssociatePy) {
  const std::vector<double> a = Stamps({0, 10, 20, 30, 40});
  const std::vector<double> b = Stamps({44, 1, 27, 11, 8});
  const Pairs pairs = AssociateStamps(a, b, 4 / 128.0);
  EXPECT_EQ(pairs, AssociatePy(a, b, 4 / 128.0));
  EXPECT_EQ(pairs, (Pairs{{0, 1}, {1, 3}, {3, 2}}));
}

// --- Pose look-up ------------------------------------------------------------------------------

// Ground truth at 100 Hz from 10.00 s to 10.02 s: the camera turns 20 deg about z and moves
// 0.1 m along x every 10 ms.
Trajectory ThreePoses() {
  Trajectory trajectory;
  for (int k = 0; k < 3; ++k) {
    trajectory.push_back({10.0 + 0.01 * k,
                          MakePoseRpy(0.0, 0.0, 20.0 * kDeg * k, Eigen::Vector3d(0.1 * k, 0.0, 1.0))});
  }
  return trajectory;
}

TEST(PoseAt, InterpolatesBetweenBracketingPoses) {
  const Trajectory trajectory = ThreePoses();
  const std::optional<Pose3> quarter = PoseAt(trajectory, 10.0025, 0.02);
  ASSERT_TRUE(quarter.has_value());
  EXPECT_TRUE(PosesNear(*quarter, MakePoseRpy(0.0, 0.0, 5.0 * kDeg, Eigen::Vector3d(0.025, 0.0, 1.0)), 1e-8,
                        1e-10));
  const std::optional<Pose3> second_half = PoseAt(trajectory, 10.015, 0.02);
  ASSERT_TRUE(second_half.has_value());
  EXPECT_TRUE(PosesNear(*second_half, MakePoseRpy(0.0, 0.0, 30.0 * kDeg, Eigen::Vector3d(0.15, 0.0, 1.0)), 1e-8,
                        1e-10));
}

TEST(PoseAt, ExactStampReturnsThatPose) {
  const Trajectory trajectory = ThreePoses();
  for (const StampedPose& p : trajectory) {
    const std::optional<Pose3> at = PoseAt(trajectory, p.stamp, 0.02);
    ASSERT_TRUE(at.has_value());
    EXPECT_TRUE(PosesNear(*at, p.T_world_camera, 1e-12, 1e-15));
  }
}

TEST(PoseAt, NearestWithinGapOutsideTheRange) {
  const Trajectory trajectory = ThreePoses();
  const std::optional<Pose3> before = PoseAt(trajectory, 9.985, 0.02);  // 15 ms before the first
  ASSERT_TRUE(before.has_value());
  EXPECT_TRUE(PosesNear(*before, trajectory.front().T_world_camera, 1e-12, 1e-15));
  const std::optional<Pose3> after = PoseAt(trajectory, 10.035, 0.02);  // 15 ms after the last
  ASSERT_TRUE(after.has_value());
  EXPECT_TRUE(PosesNear(*after, trajectory.back().T_world_camera, 1e-12, 1e-15));
}

TEST(PoseAt, NothingBeyondTheGap) {
  const Trajectory trajectory = ThreePoses();
  EXPECT_FALSE(PoseAt(trajectory, 9.97, 0.02).has_value());   // 30 ms before the first
  EXPECT_FALSE(PoseAt(trajectory, 10.05, 0.02).has_value());  // 30 ms after the last
  EXPECT_FALSE(PoseAt({}, 10.0, 0.02).has_value());
  // A tighter gap refuses what the default accepts.
  EXPECT_FALSE(PoseAt(trajectory, 9.985, 0.01).has_value());
}

TEST(PoseAt, DoesNotInterpolateAcrossALongDropout) {
  // Motion capture lost the camera for 0.5 s.
  Trajectory trajectory = {{10.0, MakePoseRpy(0.0, 0.0, 0.0, Eigen::Vector3d(0.0, 0.0, 0.0))},
                           {10.5, MakePoseRpy(0.0, 0.0, 1.0, Eigen::Vector3d(1.0, 0.0, 0.0))}};
  const std::optional<Pose3> near_start = PoseAt(trajectory, 10.01, 0.02);
  ASSERT_TRUE(near_start.has_value());
  EXPECT_TRUE(PosesNear(*near_start, trajectory[0].T_world_camera, 1e-12, 1e-15));
  const std::optional<Pose3> near_end = PoseAt(trajectory, 10.49, 0.02);
  ASSERT_TRUE(near_end.has_value());
  EXPECT_TRUE(PosesNear(*near_end, trajectory[1].T_world_camera, 1e-12, 1e-15));
  EXPECT_FALSE(PoseAt(trajectory, 10.25, 0.02).has_value());
}

TEST(PoseAt, InterpolatesAtRealTumStamps) {
  // At 1.3e9 s a double resolves about 0.24 us; the interpolation fraction stays within 1e-4.
  Trajectory trajectory = {{1305031102.1500, MakePoseRpy(0.0, 0.0, 0.0, Eigen::Vector3d(0.0, 0.0, 0.0))},
                           {1305031102.1600, MakePoseRpy(0.0, 0.0, 2.0 * kDeg, Eigen::Vector3d(0.01, 0.0, 0.0))}};
  const std::optional<Pose3> mid = PoseAt(trajectory, 1305031102.1550, 0.02);
  ASSERT_TRUE(mid.has_value());
  EXPECT_TRUE(PosesNear(*mid, MakePoseRpy(0.0, 0.0, 1.0 * kDeg, Eigen::Vector3d(0.005, 0.0, 0.0)), 1e-3, 1e-6));
}

}  // namespace
}  // namespace planemap
