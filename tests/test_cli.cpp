// The planemap executable, run as a user would: subcommands, help, output files and errors.
#include <array>
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>

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

CommandRun Planemap(const std::string& args) {
  const std::string command = std::string(PLANEMAP_BINARY) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer;
  while (size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
  const int status = pclose(pipe);
  return {WEXITSTATUS(status), output};
}

TEST(Cli, EverySubcommandHasHelp) {
  for (const char* sub : {"", "render", "inspect"}) {
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
