// planemap study: the sweep, its scores against the scene's truth, and resuming an interrupted
// study into the same CSV as an uninterrupted one.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "planemap/apps/commands.h"
#include "planemap/apps/study.h"
#include "planemap/core/error.h"
#include "test_support.h"

namespace planemap {
namespace {

using planemap::testing::TempDir;

std::string ReadFile(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// 8 runs of 3 frames: 2 distances x 2 noise levels x 2 seeds, the organized segmenter, with the
// back end.
const char* const kStudy = R"(name: test
frames: 3
seeds: 2
sweep:
  distance: [1.5, 2.0]
  noise: [1.0, 2.0]
  segmenter: [organized]
)";

std::vector<StudyRow> ReadRows(const std::string& csv) {
  std::istringstream lines(ReadFile(csv));
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, StudyCsvHeader());
  std::vector<StudyRow> rows;
  while (std::getline(lines, line)) {
    rows.emplace_back();
    EXPECT_TRUE(ParseStudyCsvLine(line, &rows.back())) << line;
  }
  return rows;
}

StudyOptions Options(const std::string& study, const std::string& out) {
  StudyOptions options;
  options.study = study;
  options.out = out;
  options.threads = 2;
  return options;
}

// One uninterrupted study, shared by the tests that read it.
class Study : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    ASSERT_EQ(RunStudy(Options(dir_->Write("study.yaml", kStudy), dir_->File("whole"))), 0);
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string Whole(const std::string& file) { return dir_->File("whole/" + file); }
  static TempDir* dir_;
};
TempDir* Study::dir_ = nullptr;

TEST_F(Study, ScoresTheBoxAgainstTheScenesTruthInCentimetresAndDegrees) {
  const std::vector<StudyRow> rows = ReadRows(Whole("runs.csv"));
  ASSERT_EQ(rows.size(), 16u);  // 8 runs, tracking and back end
  std::vector<double> dimension, center, axis;
  for (size_t i = 0; i < rows.size(); ++i) {
    const StudyRow& r = rows[i];
    EXPECT_EQ(r.run.index, static_cast<int>(i / 2));
    EXPECT_EQ(r.stage, i % 2 ? "backend" : "tracking");
    ASSERT_TRUE(r.found) << "run " << r.run.index << ": " << r.note;
    EXPECT_EQ(r.label, "box");
    EXPECT_EQ(r.frames_tracked, 3);
    EXPECT_LT(r.pose_error, 0.02) << "run " << r.run.index;  // the tracker keeps the camera within 2 cm
    if (r.run.distance != 1.5) continue;
    for (double e : r.dimension_error) {
      if (!std::isnan(e)) dimension.push_back(std::abs(e));
    }
    center.push_back(r.center_error);
    axis.push_back(r.axis_error_deg);
  }
  // At 1.5 m the box shows its top and two sides whole: issue 3's single-frame goals hold for
  // the short sequence, at the sensor's noise and at twice it.
  ASSERT_GE(dimension.size(), 16u);
  EXPECT_LE(testing::Median(dimension), 0.01);
  EXPECT_LE(testing::Median(center), 0.015);
  EXPECT_LE(testing::Median(axis), 2.0);
}

TEST_F(Study, WritesTheSummaryAndAPlotPerErrorAndSweptVariable) {
  std::istringstream summary(ReadFile(Whole("summary.csv")));
  std::string line;
  int lines = 0;
  while (std::getline(summary, line)) ++lines;
  EXPECT_EQ(lines, 1 + 8);  // header, 4 cells x 2 stages
  for (const char* plot : {"dimension_vs_distance.svg", "center_vs_distance.svg", "axis_vs_distance.svg",
                           "dimension_vs_noise.svg", "center_vs_noise.svg", "axis_vs_noise.svg"}) {
    EXPECT_NE(ReadFile(Whole(plot)).find("<polyline"), std::string::npos) << plot;
  }
  EXPECT_FALSE(std::filesystem::exists(Whole("dimension_vs_object_scale.svg")));  // one value: no plot
}

TEST_F(Study, AStudyStoppedAndResumedGivesTheSameCsvAsAnUninterruptedOne) {
  TempDir dir;
  const std::string study = dir.Write("study.yaml", kStudy);
  StudyOptions options = Options(study, dir.File("parts"));
  options.max_runs = 3;  // stops as an interrupted run does: finished runs kept, no summary yet
  ASSERT_EQ(RunStudy(options), 0);
  EXPECT_FALSE(std::filesystem::exists(dir.File("parts/summary.csv")));
  EXPECT_EQ(ReadRows(dir.File("parts/runs.csv")).size(), 6u);
  // A write the interruption cut: half a line, no newline. It is dropped and its run redone.
  std::ofstream(dir.File("parts/runs.csv"), std::ios::app) << "fig2,7,2,45,2,1,organized,2,track";
  options.max_runs = 2;
  ASSERT_EQ(RunStudy(options), 0);
  options.max_runs = 0;
  ASSERT_EQ(RunStudy(options), 0);
  EXPECT_EQ(ReadFile(dir.File("parts/runs.csv")), ReadFile(Whole("runs.csv")));
  EXPECT_EQ(ReadFile(dir.File("parts/summary.csv")), ReadFile(Whole("summary.csv")));
}

TEST_F(Study, CtrlCKeepsTheFinishedRunsAndTheNextInvocationCompletesTheSameCsv) {
  TempDir dir;
  const std::string study = dir.Write("study.yaml", kStudy);
  const std::string out = dir.File("ctrl_c");
  // The tool in the background; SIGINT once two runs are in the CSV (header + 4 lines), as a user
  // pressing Ctrl-C. A shell's background job ignores SIGINT until the tool installs its handler,
  // which it does before it runs anything.
  const std::string script = std::string(PLANEMAP_BINARY) + " study " + study + " --out " + out +
                             " --threads 1 >/dev/null 2>&1 & pid=$!; n=0; "
                             "while [ \"$(wc -l < " + out + "/runs.csv 2>/dev/null || echo 0)\" -lt 5 ] && [ $n -lt 1200 ]; "
                             "do sleep 0.1; n=$((n+1)); done; kill -INT $pid; wait $pid; echo $? > " + out + ".exit";
  ASSERT_EQ(std::system(("bash -c '" + script + "'").c_str()), 0);
  EXPECT_EQ(ReadFile(out + ".exit"), "130\n");
  const size_t kept = ReadRows(out + "/runs.csv").size();
  EXPECT_GE(kept, 4u);
  EXPECT_LT(kept, 16u);
  ASSERT_EQ(RunStudy(Options(study, out)), 0);
  EXPECT_EQ(ReadFile(out + "/runs.csv"), ReadFile(Whole("runs.csv")));
}

TEST_F(Study, RefusesToResumeIntoAFolderOfAStudyWithOtherSettings) {
  TempDir dir;
  std::string changed = kStudy;
  changed.replace(changed.find("seeds: 2"), 8, "seeds: 3");
  StudyOptions options = Options(dir.Write("study.yaml", changed), dir.File("other"));
  std::filesystem::copy(Whole(""), dir.File("other"), std::filesystem::copy_options::recursive);
  try {
    RunStudy(options);
    FAIL() << "resumed another study's runs";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("other settings"), std::string::npos) << e.what();
  }
  options.restart = true;  // ... unless told to start over
  options.max_runs = 1;
  EXPECT_EQ(RunStudy(options), 0);
  EXPECT_EQ(ReadRows(dir.File("other/runs.csv")).size(), 2u);
}

TEST(StudySweep, ViewingAngleAndObjectSizeChangeWhatIsRenderedAndScored) {
  // The box scaled to 0.8 and 1.2 of its size (sitting on the floor) and seen from 30 and 60 deg
  // off its +x face: each is found and measured against its scaled truth, within 1 cm.
  TempDir dir;
  const std::string study = dir.Write("study.yaml", R"(name: angle_size
frames: 1
seeds: 1
backend: false
sweep:
  distance: [1.5]
  viewing_angle_deg: [30, 60]
  object_scale: [0.8, 1.2]
)");
  // The rendered box is the scaled one: 0.25 x 0.35 x 0.25 m times 1.2, still on the floor.
  const sim::Scene scaled = StudyScene(LoadStudy(study), 1.2);
  const sim::SceneObject& big = scaled.object("box");
  EXPECT_NEAR(big.dimensions.x(), 0.30, 1e-9);
  EXPECT_NEAR(big.dimensions.y(), 0.42, 1e-9);
  EXPECT_NEAR(big.T_world_object.translation().z() - 0.5 * big.dimensions.z(), 0.0, 1e-9);
  StudyOptions options = Options(study, dir.File("out"));
  ASSERT_EQ(RunStudy(options), 0);
  const std::vector<StudyRow> rows = ReadRows(dir.File("out/runs.csv"));
  ASSERT_EQ(rows.size(), 4u);
  for (const StudyRow& r : rows) {
    SCOPED_TRACE("angle " + std::to_string(r.run.viewing_angle_deg) + ", scale " + std::to_string(r.run.object_scale));
    ASSERT_TRUE(r.found) << r.note;
    EXPECT_EQ(r.label, "box");
    int measured = 0;
    for (double e : r.dimension_error) {
      if (std::isnan(e)) continue;
      ++measured;
      EXPECT_LT(std::abs(e), 0.01);
    }
    EXPECT_GE(measured, 2);
    EXPECT_LT(r.center_error, 0.015);
    EXPECT_LT(r.axis_error_deg, 2.0);
  }
  for (const char* plot : {"dimension_vs_viewing_angle.svg", "center_vs_object_scale.svg"}) {
    EXPECT_TRUE(std::filesystem::exists(dir.File(std::string("out/") + plot))) << plot;
  }
}

TEST(StudyFile, ImpossibleViewpointsAndUnknownNamesAreErrorsNamingTheFile) {
  TempDir dir;
  const auto error = [&](const std::string& text) {
    const std::string file = dir.Write("bad.yaml", text);
    try {
      LoadStudy(file);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("sweep: {distance: [9.0]}").find("outside the floor"), std::string::npos);
  EXPECT_NE(error("sweep: {segmenter: [ransac]}").find("unknown segmenter 'ransac'"), std::string::npos);
  EXPECT_NE(error("object: table").find("no object 'table'"), std::string::npos);
  EXPECT_NE(error("sweep: {noise: []}").find("at least one value"), std::string::npos);
  EXPECT_NE(error("sweep: {noise: [-1]}").find("noise"), std::string::npos);
  EXPECT_NE(error("frames: 3\nsweeep: {}").find("sweeep"), std::string::npos);
}

TEST(StudyCsv, ALineReadsBackAsTheRowItWasWrittenFrom) {
  StudyRow row;
  row.source = "fig2";
  row.run = {17, 2.5, 30.0, 0.5, 1.25, "msac", 3};
  row.stage = "backend";
  row.found = true;
  row.label = "box";
  row.class_ok = true;
  row.dimension_error[0] = 0.0123;
  row.dimension_error[2] = -0.0045;
  row.center_error = 0.0071;
  row.axis_error_deg = 1.5;
  row.frames_tracked = 5;
  row.pose_error = 0.004;
  row.note = "a, b";
  StudyRow back;
  ASSERT_TRUE(ParseStudyCsvLine(StudyCsvLine(row), &back));
  EXPECT_EQ(back.run.index, 17);
  EXPECT_EQ(back.run.segmenter, "msac");
  EXPECT_DOUBLE_EQ(back.run.object_scale, 1.25);
  EXPECT_NEAR(back.dimension_error[0], 0.0123, 1e-9);
  EXPECT_TRUE(std::isnan(back.dimension_error[1]));
  EXPECT_TRUE(std::isnan(back.grasp_axis_error_deg));
  EXPECT_NEAR(back.pose_error, 0.004, 1e-9);
  EXPECT_EQ(back.note, "a; b");  // commas never split a field
  EXPECT_EQ(back.source, "fig2");
  EXPECT_FALSE(ParseStudyCsvLine("fig2,17,2.5,30,0.5", &back));
}

}  // namespace
}  // namespace planemap
