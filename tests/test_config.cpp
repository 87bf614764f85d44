// YAML configs: camera files, the default app config, and errors that name file, line and key.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "planemap/apps/app_config.h"
#include "planemap/core/config.h"
#include "planemap/core/error.h"
#include "planemap/core/intrinsics.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

using planemap::testing::SourcePath;
using planemap::testing::TempDir;
using planemap::testing::ThrowsWith;

std::vector<std::string> CameraFiles() {
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(SourcePath("configs/cameras"))) {
    if (entry.path().extension() == ".yaml") files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(CameraFiles, EveryFileLoadsAndValidates) {
  const std::vector<std::string> files = CameraFiles();
  ASSERT_GE(files.size(), 6u);
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    CameraIntrinsics camera;
    ASSERT_NO_THROW(camera = LoadCameraIntrinsics(file));
    EXPECT_NO_THROW(ValidateConfig(camera));
    // Every shipped camera is a VGA sensor with its principal point inside the image.
    EXPECT_EQ(camera.width, 640);
    EXPECT_EQ(camera.height, 480);
    EXPECT_GT(camera.cx, 0.0);
    EXPECT_LT(camera.cx, camera.width);
    EXPECT_GT(camera.cy, 0.0);
    EXPECT_LT(camera.cy, camera.height);
    // Focal lengths of Kinect / Xtion class cameras [px].
    EXPECT_GT(camera.fx, 400.0);
    EXPECT_LT(camera.fx, 650.0);
    EXPECT_GT(camera.fy, 400.0);
    EXPECT_LT(camera.fy, 650.0);
  }
}

TEST(CameraFiles, SpotCheckValues) {
  const CameraIntrinsics fr1 = LoadCameraIntrinsics(SourcePath("configs/cameras/tum_fr1.yaml"));
  EXPECT_DOUBLE_EQ(fr1.fx, 517.3);
  EXPECT_DOUBLE_EQ(fr1.fy, 516.5);
  EXPECT_DOUBLE_EQ(fr1.cx, 318.6);
  EXPECT_DOUBLE_EQ(fr1.cy, 255.3);
  EXPECT_DOUBLE_EQ(fr1.depth_scale, 5000.0);

  const CameraIntrinsics xtion = LoadCameraIntrinsics(SourcePath("configs/cameras/xtion_nao.yaml"));
  EXPECT_DOUBLE_EQ(xtion.depth_scale, 1000.0);  // millimetres
  EXPECT_DOUBLE_EQ(xtion.fx, 570.3);

  const CameraIntrinsics fr3 = LoadCameraIntrinsics(SourcePath("configs/cameras/tum_fr3.yaml"));
  EXPECT_DOUBLE_EQ(fr3.depth_scale, 5000.0);
  EXPECT_DOUBLE_EQ(fr3.fx, 535.4);
  EXPECT_DOUBLE_EQ(fr3.fy, 539.2);

  const CameraIntrinsics openni = LoadCameraIntrinsics(SourcePath("configs/cameras/tum_openni_default.yaml"));
  EXPECT_DOUBLE_EQ(openni.fx, 525.0);
  EXPECT_DOUBLE_EQ(openni.cx, 319.5);
  EXPECT_DOUBLE_EQ(openni.cy, 239.5);
}

// A key left out used to take the TUM/OpenNI default: a 600 px camera read with fy 525 and
// depth_scale 5000 (a millimetre sensor's depths 5x too short), without a word.
TEST(CameraFiles, ACalibrationGivesEveryKey) {
  TempDir dir;
  const std::string partial = dir.Write("partial.yaml", "fx: 600.0\nfy: 600.0\ncx: 320\ncy: 240\nwidth: 640\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(partial); }, {partial, "missing: height, depth_scale"}));
  const std::string empty = dir.Write("empty.yaml", "");
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(empty); }, {empty, "missing: fx, fy, cx, cy, width, height, depth_scale"}));
  const std::string full = dir.Write("full.yaml", "fx: 600.0\nfy: 601.0\ncx: 320\ncy: 240\nwidth: 640\nheight: 480\ndepth_scale: 1000\n");
  const CameraIntrinsics camera = LoadCameraIntrinsics(full);
  EXPECT_DOUBLE_EQ(camera.fy, 601.0);
  EXPECT_DOUBLE_EQ(camera.depth_scale, 1000.0);
}

TEST(AppConfigFile, DefaultYamlEqualsTheDefaultsInCode) {
  const AppConfig loaded = LoadConfigFile<AppConfig>(SourcePath("configs/default.yaml"));
  const AppConfig defaults;
  EXPECT_EQ(YAML::Dump(ConfigToYaml(loaded)), YAML::Dump(ConfigToYaml(defaults)));
  EXPECT_NO_THROW(ValidateConfig(loaded));
  EXPECT_DOUBLE_EQ(loaded.dataset.max_association_gap, 0.02);  // [s]
  EXPECT_DOUBLE_EQ(loaded.render.noise.sigma_coefficient, 0.001425);
}

TEST(AppConfigFile, WrittenConfigReadsBackEqual) {
  TempDir dir;
  AppConfig config;
  config.dataset.max_association_gap = 0.033;
  config.render.noise.max_depth = 5.5;
  config.render.add_noise = false;
  config.render.light_direction = {0.0, -1.0, 2.0};
  const std::string file = dir.File("app.yaml");
  SaveYamlFile(ConfigToYaml(config), file);
  const AppConfig loaded = LoadConfigFile<AppConfig>(file);
  EXPECT_EQ(YAML::Dump(ConfigToYaml(loaded)), YAML::Dump(ConfigToYaml(config)));
  EXPECT_DOUBLE_EQ(loaded.dataset.max_association_gap, 0.033);
  EXPECT_DOUBLE_EQ(loaded.render.noise.max_depth, 5.5);
}

TEST(AppConfigFile, EmptyFileGivesDefaults) {
  TempDir dir;
  const std::string file = dir.Write("empty.yaml", "# nothing set\n");
  const AppConfig loaded = LoadConfigFile<AppConfig>(file);
  const AppConfig defaults;
  EXPECT_EQ(YAML::Dump(ConfigToYaml(loaded)), YAML::Dump(ConfigToYaml(defaults)));
}

// --- Errors ------------------------------------------------------------------------------------

TEST(ConfigErrors, UnknownTopLevelKey) {
  TempDir dir;
  const std::string file = dir.Write("bad.yaml", "fx: 500.0\nfy: 500.0\nfocal: 500.0\n");
  EXPECT_THROW(LoadCameraIntrinsics(file), InputError);
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(file); }, {file + ":3", "focal"}));
}

TEST(ConfigErrors, UnknownNestedKey) {
  TempDir dir;
  const std::string file = dir.Write("bad.yaml",
                                     "dataset:\n"
                                     "  max_association_gap: 0.02\n"
                                     "render:\n"
                                     "  ambient: 0.3\n"
                                     "  noise:\n"
                                     "    gaussian: true\n"
                                     "    sigma_coef: 0.002\n");
  EXPECT_THROW(LoadConfigFile<AppConfig>(file), InputError);
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(file); }, {file + ":7", "render.noise.sigma_coef"}));
}

TEST(ConfigErrors, StringWhereANumberIsExpected) {
  TempDir dir;
  const std::string file = dir.Write("bad.yaml", "fx: 525.0\nfy: five hundred\n");
  EXPECT_THROW(LoadCameraIntrinsics(file), InputError);
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(file); }, {file + ":2", "fy", "five hundred"}));

  const std::string nested = dir.Write("nested.yaml", "render:\n  noise:\n    max_depth: far\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(nested); }, {nested + ":3", "render.noise.max_depth"}));
}

TEST(ConfigErrors, StringWhereAnIntegerIsExpected) {
  TempDir dir;
  const std::string file = dir.Write("bad.yaml", "width: 640.5\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(file); }, {file + ":1", "width"}));
}

TEST(ConfigErrors, NanValue) {
  TempDir dir;
  const std::string file = dir.Write("bad.yaml", "fx: 525.0\nfy: 525.0\ncx: .nan\n");
  EXPECT_THROW(LoadCameraIntrinsics(file), InputError);
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(file); }, {file + ":3", "cx", "finite"}));
  // NaN is refused even where any value is allowed (Check::kAny).
  const std::string light = dir.Write("light.yaml", "render:\n  light_direction: [0.0, .nan, 1.0]\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(light); }, {light + ":2", "render.light_direction"}));
}

TEST(ConfigErrors, NegativeFocalLength) {
  TempDir dir;
  const std::string file = dir.Write("bad.yaml", "fx: -525.0\n");
  EXPECT_THROW(LoadCameraIntrinsics(file), InputError);
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(file); }, {file + ":1", "fx", "> 0"}));
}

TEST(ConfigErrors, ZeroWidth) {
  TempDir dir;
  const std::string file = dir.Write("bad.yaml", "fx: 525.0\nwidth: 0\nheight: 480\n");
  EXPECT_THROW(LoadCameraIntrinsics(file), InputError);
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(file); }, {file + ":2", "width", "> 0"}));
}

TEST(ConfigErrors, ProbabilityOutOfRange) {
  TempDir dir;
  const std::string file = dir.Write("bad.yaml", "render:\n  noise:\n    edge_dropout_probability: 1.5\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(file); },
                         {file + ":3", "render.noise.edge_dropout_probability", "[0, 1]"}));
}

TEST(ConfigErrors, ScalarWhereAMapIsExpected) {
  TempDir dir;
  const std::string file = dir.Write("bad.yaml", "dataset: 0.02\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(file); }, {file + ":1", "dataset"}));
}

TEST(ConfigErrors, MissingFile) {
  TempDir dir;
  const std::string file = dir.File("does_not_exist.yaml");
  EXPECT_THROW(LoadCameraIntrinsics(file), InputError);
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(file); }, {file, "cannot open"}));
}

TEST(ConfigErrors, YamlSyntaxError) {
  TempDir dir;
  // An unclosed flow sequence on line 3.
  const std::string file = dir.Write("bad.yaml", "fx: 525.0\nfy: 525.0\ncx: [319.5\n");
  EXPECT_THROW(LoadCameraIntrinsics(file), InputError);
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(file); }, {file + ":", "YAML syntax error"}));

  // A bad indentation on line 2 reports line 2.
  const std::string indent = dir.Write("indent.yaml", "fx: 525.0\n  fy: 525.0\ncx: 1\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(indent); }, {indent + ":2", "YAML syntax error"}));
}

TEST(ConfigErrors, TopLevelNotAMap) {
  TempDir dir;
  const std::string file = dir.Write("bad.yaml", "- 1\n- 2\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(file); }, {file, "map"}));
}

TEST(ConfigErrors, AStringOutsideItsChoicesNamesTheFileLineAndChoices) {
  TempDir dir;
  // Each was found only when the setting was used: the back end's loss once tracking had run.
  const std::string loss = dir.Write("loss.yaml", "backend:\n  loss:\n    type: tukey\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(loss); },
                         {loss + ":3", "backend.loss.type", "huber, cauchy, soft_l1 or none", "'tukey'"}));
  const std::string method = dir.Write("method.yaml", "frontend:\n  segmentation:\n    method: ransac\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(method); },
                         {method + ":3", "frontend.segmentation.method", "organized or msac", "'ransac'"}));
  const std::string refine = dir.Write("refine.yaml", "tracking:\n  refine: gicp\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(refine); }, {refine + ":2", "tracking.refine", "'gicp'"}));
  // Built in code: the same check, naming the field.
  AppConfig config;
  config.backend.linear_solver = "dense_qr";
  EXPECT_TRUE(ThrowsWith([&] { ValidateConfig(config); }, {"backend.linear_solver", "sparse_schur or sparse_normal_cholesky"}));
}

TEST(ConfigErrors, SettingsThatContradictEachOtherAreNamed) {
  TempDir dir;
  // A depth window with nothing in it made every pixel invalid: an empty model, no error.
  const std::string depths = dir.Write("depths.yaml", "frontend:\n  cloud:\n    min_depth: 7.0\n    max_depth: 6.0\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(depths); },
                         {depths + ":3", "frontend.cloud", "min_depth 7 must be below max_depth 6"}));
  // A zero up vector normalized to NaN: no floor, no object height, silently.
  const std::string up = dir.Write("up.yaml", "frontend:\n  graph:\n    up_in_camera: [0, 0, 0]\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(up); }, {up + ":3", "frontend.graph", "up_in_camera must not be zero"}));
  const std::string two = dir.Write("two.yaml", "frontend:\n  graph:\n    up_in_camera: [0, -1]\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(two); }, {two + ":3", "up_in_camera needs 3 numbers"}));
  const std::string noise = dir.Write("noise.yaml", "render:\n  noise:\n    min_depth: 5.0\n    max_depth: 0.5\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(noise); }, {noise + ":3", "render.noise", "must be below max_depth"}));
  // Built in code: the same, naming the struct.
  AppConfig config;
  config.frontend.objects.hand_span_min = 0.5;
  EXPECT_TRUE(ThrowsWith([&] { ValidateConfig(config); }, {"frontend.objects is inconsistent", "hand_span_min"}));
  CloudConfig cloud;
  cloud.min_depth = 9.0;
  EXPECT_TRUE(ThrowsWith([&] { ValidateConfig(cloud, "cloud."); }, {"cloud is inconsistent", "min_depth"}));
}

TEST(ConfigErrors, ADirectoryIsNotAFile) {
  TempDir dir;
  // std::ifstream opens a directory; reading it threw "basic_filebuf::underflow ... Is a directory".
  EXPECT_TRUE(ThrowsWith([&] { LoadConfigFile<AppConfig>(dir.path()); }, {dir.path(), "is a directory"}));
  EXPECT_TRUE(ThrowsWith([&] { LoadCameraIntrinsics(dir.path()); }, {dir.path(), "is a directory"}));
}

TEST(ValidateConfig, StructBuiltInCodeWithNegativeFx) {
  CameraIntrinsics camera;
  camera.fx = -1.0;
  EXPECT_THROW(ValidateConfig(camera), std::invalid_argument);
  EXPECT_TRUE(ThrowsWith([&] { ValidateConfig(camera); }, {"fx", "> 0"}));
  EXPECT_TRUE(ThrowsWith([&] { ValidateConfig(camera, "camera."); }, {"camera.fx"}));
}

TEST(ValidateConfig, NestedFieldIsNamedWithItsPath) {
  AppConfig config;
  config.render.noise.max_depth = std::nan("");
  EXPECT_THROW(ValidateConfig(config), std::invalid_argument);
  EXPECT_TRUE(ThrowsWith([&] { ValidateConfig(config); }, {"render.noise.max_depth", "finite"}));
}

TEST(ValidateConfig, DefaultsPass) {
  EXPECT_NO_THROW(ValidateConfig(CameraIntrinsics{}));
  const AppConfig defaults;
  EXPECT_NO_THROW(ValidateConfig(defaults));
}

}  // namespace
}  // namespace planemap
