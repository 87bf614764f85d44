// The planemap executable, run as a user would: subcommands, help, output files and errors.
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "planemap/core/tum_format.h"
#include "test_support.h"

namespace planemap {
namespace {

using planemap::testing::SourcePath;
using planemap::testing::TempDir;

struct CommandRun {
  int exit_code;
  std::string output;  // stdout and stderr
};

// Runs planemap with `args`; its output is stdout and stderr, or stdout alone.
CommandRun Planemap(const std::string& args, bool with_stderr = true) {
  const std::string command = std::string(PLANEMAP_BINARY) + " " + args + (with_stderr ? " 2>&1" : " 2>/dev/null");
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer;
  while (size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
  const int status = pclose(pipe);
  return {WEXITSTATUS(status), output};
}

TEST(Cli, EverySubcommandHasHelp) {
  for (const char* sub : {"", "render", "inspect", "frame"}) {
    const CommandRun run = Planemap(std::string(sub) + " --help");
    EXPECT_EQ(run.exit_code, 0) << sub;
    EXPECT_NE(run.output.find("Usage"), std::string::npos) << run.output;
  }
}

TEST(Cli, RenderWritesAReadableSequence) {
  TempDir dir;
  const std::string out = dir.File("seq");
  const CommandRun render = Planemap("render --max-frames 3 --out " + out + " --scene " +
                              SourcePath("configs/scenes/default.yaml") + " --trajectory " +
                              SourcePath("configs/walks/default.yaml"));
  ASSERT_EQ(render.exit_code, 0) << render.output;
  EXPECT_NE(render.output.find("wrote 3 frames"), std::string::npos) << render.output;
  for (const char* file : {"rgb.txt", "depth.txt", "label.txt", "groundtruth.txt", "associations.txt",
                           "scene.yaml", "scene_groundtruth.yaml", "camera.yaml", "config.yaml"}) {
    EXPECT_TRUE(std::filesystem::exists(out + "/" + file)) << file;
  }
  // The ground truth is the default walk's start: 0.52 m above the floor at the origin.
  const Trajectory gt = ReadTumTrajectory(out + "/groundtruth.txt");
  ASSERT_EQ(gt.size(), 3u);
  EXPECT_NEAR(gt[0].T_world_camera.translation().z(), 0.52, 1e-6);
  // The sequence's own camera.yaml is used by default; another camera is refused, not misread.
  const CommandRun inspect = Planemap("inspect " + out);
  ASSERT_EQ(inspect.exit_code, 0) << inspect.output;
  EXPECT_NE(inspect.output.find("3 associated frames"), std::string::npos) << inspect.output;
  EXPECT_NE(inspect.output.find("3 of 3 read frames have a pose"), std::string::npos) << inspect.output;
  EXPECT_NE(inspect.output.find("1000 depth units per metre"), std::string::npos) << inspect.output;
  const CommandRun mismatch =
      Planemap("inspect " + out + " --camera " + SourcePath("configs/cameras/tum_openni_default.yaml"));
  EXPECT_EQ(mismatch.exit_code, 1);
  EXPECT_NE(mismatch.output.find(out + "/camera.yaml: the sequence was written with another camera"),
            std::string::npos) << mismatch.output;
}

TEST(Cli, FramePrintsTheModelAsJsonAndWritesOverlayAndPly) {
  TempDir dir;
  const std::string seq = dir.File("seq");
  ASSERT_EQ(Planemap("render --max-frames 1 --out " + seq).exit_code, 0);
  const CommandRun frame = Planemap("frame --sequence " + seq + " --index 0 --out " + dir.File("frame"), false);
  ASSERT_EQ(frame.exit_code, 0) << frame.output;
  const nlohmann::json model = nlohmann::json::parse(frame.output);
  int boxes = 0;
  for (const auto& object : model["objects"]) {
    if (object["class"] != "box") continue;
    ++boxes;
    // The default scene's box from the start pose: 0.25 x 0.35 x 0.25 m; its sides are measured.
    std::vector<double> dims = object["dimensions"].get<std::vector<double>>();
    std::sort(dims.begin(), dims.end());
    EXPECT_NEAR(dims[2], 0.35, 0.02);
  }
  EXPECT_EQ(boxes, 1) << frame.output;
  EXPECT_GE(model["planes"].size(), 3u);
  for (const char* file : {"model.json", "model.ply", "overlay.png"}) {
    EXPECT_GT(std::filesystem::file_size(dir.File("frame/") + file), 100u) << file;
  }
  const CommandRun two = Planemap("frame --sequence " + seq + " --pcd x.pcd");
  EXPECT_EQ(two.exit_code, 1);
  EXPECT_NE(two.output.find("give exactly one frame source"), std::string::npos) << two.output;
  const CommandRun missing = Planemap("frame --sequence " + seq + " --index 5");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find("frame 5 does not exist (1 frames)"), std::string::npos) << missing.output;
}

TEST(Cli, ErrorsAreOneLineNamingTheFileAndExitNonZero) {
  TempDir dir;
  const CommandRun missing = Planemap("render --scene " + dir.File("nope.yaml") + " --out " + dir.File("o"));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find("planemap render: error: " + dir.File("nope.yaml") + ": cannot open file"),
            std::string::npos) << missing.output;
  EXPECT_EQ(std::count(missing.output.begin(), missing.output.end(), '\n'), 1) << missing.output;

  const std::string bad_camera = dir.Write("cam.yaml", "fx: 525\nfy: -1\n");
  const CommandRun camera = Planemap("inspect " + dir.path() + " --camera " + bad_camera);
  EXPECT_EQ(camera.exit_code, 1);
  EXPECT_NE(camera.output.find(bad_camera + ":2: key 'fy' must be > 0"), std::string::npos) << camera.output;

  const CommandRun no_sequence = Planemap("inspect " + dir.File("no_such_sequence"));
  EXPECT_EQ(no_sequence.exit_code, 1);
  EXPECT_NE(no_sequence.output.find("sequence folder does not exist"), std::string::npos) << no_sequence.output;

  const CommandRun unknown = Planemap("fly");
  EXPECT_NE(unknown.exit_code, 0);
}

}  // namespace
}  // namespace planemap
