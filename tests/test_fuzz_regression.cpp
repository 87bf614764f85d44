// What the fuzz targets (fuzz/, docs/fuzzing.md) found: each input in tests/data/fuzz/<target>/,
// read through the function the tool calls, as the target drove it. Each used to crash the tool
// (or be undefined behaviour); each must now be an InputError naming the file and what is wrong.
#include <string>

#include <gtest/gtest.h>

#include "planemap/apps/study.h"
#include "planemap/core/error.h"
#include "planemap/frontend/pcd_source.h"
#include "planemap/io/plane_map_io.h"
#include "planemap/sim/scene.h"
#include "test_support.h"

namespace planemap {
namespace {

std::string FuzzInput(const std::string& target, const std::string& name) {
  return testing::SourcePath("tests/data/fuzz/" + target + "/" + name);
}

// `read(file)` throws an InputError naming `file` and saying `what`.
template <class Read>
::testing::AssertionResult ThrowsInputError(const std::string& file, Read read, const std::string& what) {
  return testing::ThrowsWith<InputError>([&] { read(file); }, {file, what});
}

// A PCD input of fuzz_pcd (its 8x6 camera) read as `planemap frame --pcd` does.
::testing::AssertionResult PcdInputError(const std::string& name, const std::string& what) {
  CameraIntrinsics camera;
  camera.width = 8;
  camera.height = 6;
  return ThrowsInputError(FuzzInput("pcd", name), [&](const std::string& file) { LoadOrganizedPcd(file, camera); }, what);
}

// PCL's header reader threw std::out_of_range at a DATA line without its kind (ascii, binary, ...);
// it escaped the reader and named no file. The header check (the format's grammar, before PCL)
// now stops it at its first bad line, a VIEWPOINT holding NULs.
TEST(FuzzRegression, PcdDataLineWithoutKind) {
  EXPECT_TRUE(PcdInputError("data_line_without_kind.pcd", ":9: not a PCD file (a header line holds the byte 0x00)"));
}

// A SIZE line's value beyond any type (44444444444444444444444444, read by PCL as a huge size):
// PCL's header reader allocated width x height x that (206 GB) before reading a point.
TEST(FuzzRegression, PcdSizeBeyondAnyType) {
  EXPECT_TRUE(PcdInputError("size_beyond_any_type.pcd", ":3: not a PCD file (SIZE '44444444444444444444444444' is no number)"));
}

// A header without SIZE lines whose POINTS line claims 307207120 points (the line goes on with
// bytes that are no number): PCL allocated for them (85 GB) before reading one. Its WIDTH line
// comes before any FIELDS.
TEST(FuzzRegression, PcdPointsBeyondTheCamera) {
  EXPECT_TRUE(PcdInputError("points_beyond_the_camera.pcd", ":2: not a PCD file (no FIELDS before WIDTH)"));
}

// A binary cloud with two headers: PCL's reader sized the data by the first (16-byte points) and
// the fields by the second (20 bytes), and its conversion to pcl::PointXYZRGBL copied past the
// data's end (heap-buffer-overflow in pcl::fromPCLPointCloud2). The header check refuses a second
// header (here first a VIEWPOINT holding NULs), and the points are taken from PCL's raw blob field
// by field, its length and each offset checked, no longer by PCL's conversion.
TEST(FuzzRegression, PcdOverflowInPclConversion) {
  EXPECT_TRUE(PcdInputError("overflow_in_pcl_conversion.pcd", ":9: not a PCD file (a header line holds the byte 0x00)"));
}

// A binary_compressed cloud whose block says it holds 0 bytes, compressed and whole: PCL's reader
// warned and then copied from a null map (SEGV in pcl::PCDReader::readBodyBinary). The block's
// sizes are now checked against the file and the points before PCL reads it.
TEST(FuzzRegression, PcdCompressedBlockOfNothing) {
  EXPECT_TRUE(PcdInputError("compressed_block_of_nothing.pcd",
                      "truncated or corrupt: its compressed block of 0 bytes, 71 in the file, says it holds 0 bytes; "
                      "48 points take 768)"));
}

// A binary cloud whose data begins with "COLUMNS": PCL's header reader goes on past DATA, took
// that line for a FIELDS line (the points 4,506 bytes apart) and read far past the data (SEGV in
// pcl::PCDReader::readBodyBinary). A line after DATA that PCL would read as header is refused.
TEST(FuzzRegression, PcdDataBeginningWithAKey) {
  EXPECT_TRUE(PcdInputError("data_beginning_with_a_key.pcd",
                      ":12: not a PCD file (a line after DATA begins with COLUMNS, which PCL's reader takes as more header)"));
}

// A header with a line of a lone carriage return before FIELDS: PCL skips empty lines but ends
// its header at that one, and its read() of the points then dereferenced null (SEGV in
// pcl::PCDReader::read). Such a line is refused, and PCL's header reader runs alone first.
TEST(FuzzRegression, PcdWhiteSpaceLineInHeader) {
  EXPECT_TRUE(PcdInputError("white_space_line_in_header.pcd", ":3: not a PCD file (a header line of white space only)"));
}

// A key that is no name (here a null one in a wall's flow map) threw YAML::BadConversion from
// every config and scene reader's unknown-key check, an error naming no file.
TEST(FuzzRegression, SceneKeyNotAName) {
  EXPECT_TRUE(ThrowsInputError(FuzzInput("scene_yaml", "key_not_a_name.yaml"), [](const std::string& file) { sim::LoadScene(file); },
                   ":18: a key in 'walls[1]' is not a name"));
}

// An object's evidence counts beyond int's range were cast to int: undefined behaviour (UBSan).
TEST(FuzzRegression, MapJsonCountBeyondInt) {
  EXPECT_TRUE(ThrowsInputError(FuzzInput("map_json", "complete_count_beyond_int.json"),
                   [](const std::string& file) { ReadPlaneMapJson(file); },
                   "objects[0].evidence.complete_count[0]: expected an integer, got 20000000000.0"));
}

// 100,000,000 seeds per cell: LoadStudy listed 3e9 runs and checked their viewpoints, loading
// the scene once per cell, for minutes before running out of memory (a hang to the fuzz target).
TEST(FuzzRegression, StudyWithAHundredMillionSeeds) {
  EXPECT_TRUE(ThrowsInputError(FuzzInput("study_yaml", "hundred_million_seeds.yaml"), [](const std::string& file) { LoadStudy(file); },
                   "the sweep's 3000000000 runs of 5 frames are more than the 1000000 frames one study may render"));
}

// A study whose config: names a file over 255 bytes: std::filesystem::exists threw
// filesystem_error (ENAMETOOLONG) from ResolveConfigPath, an error naming no input file. The
// paths the tool is given are now looked up with the error_code forms, and the error names the
// settings file the study refers to, as for any settings file that cannot be opened.
TEST(FuzzRegression, StudyConfigNameTooLong) {
  EXPECT_TRUE(testing::ThrowsWith<InputError>([] { LoadStudy(FuzzInput("study_yaml", "config_name_too_long.yaml")); },
                                              {"con  \xC9\xC9\xC9",  // the config: value, as the study gives it
                                               ": cannot open file"}));
}

}  // namespace
}  // namespace planemap
