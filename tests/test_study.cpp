// planemap study: the sweep, its scores against the scene's truth, and resuming an interrupted
// study into the same CSV as an uninterrupted one.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "planemap/apps/commands.h"
#include "planemap/apps/study.h"
#include "planemap/core/error.h"
#include "test_support.h"

namespace planemap {
namespace {

using planemap::testing::SourcePath;
using planemap::testing::TempDir;
using planemap::testing::ThrowsWith;
namespace fs = std::filesystem;

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

// Every file of a folder (not its subfolders: a collected study's shards/), by name.
std::map<std::string, std::string> Files(const std::string& folder) {
  std::map<std::string, std::string> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (entry.is_regular_file()) files[entry.path().filename().string()] = ReadFile(entry.path().string());
  }
  return files;
}

std::vector<int> RunIndices(const std::string& csv) {
  std::vector<int> indices;
  for (const StudyRow& row : ReadRows(csv)) {
    if (row.stage == "tracking") indices.push_back(row.run.index);
  }
  return indices;
}

TEST_F(Study, ThreeShardsCollectedAreTheStudyRunWholeByteForByte) {
  TempDir dir;
  const std::string study = dir.Write("study.yaml", kStudy);
  const std::string out = dir.File("sharded");
  // Each shard in its own folder, with the runs dealt to it; the shards run in any order, as a
  // job array's tasks start.
  std::vector<int> dealt;
  for (int k : {3, 1, 2}) {
    StudyOptions options = Options(study, out);
    options.shard = std::to_string(k) + "/3";
    options.threads = 1;
    ASSERT_EQ(RunStudy(options), 0);
    const std::vector<int> indices = RunIndices(out + "/shards/" + std::to_string(k) + "-of-3/runs.csv");
    std::vector<int> expected;
    for (const StudyRun& run : ShardRuns(StudyRuns(LoadStudy(study)), {k, 3})) expected.push_back(run.index);
    EXPECT_EQ(indices, expected) << "shard " << k;
    EXPECT_GE(indices.size(), 2u);
    dealt.insert(dealt.end(), indices.begin(), indices.end());
  }
  std::sort(dealt.begin(), dealt.end());
  EXPECT_EQ(dealt, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_TRUE(Files(out).empty());  // a shard writes into its own folder only
  StudyOptions collect = Options(study, out);
  collect.collect = true;
  ASSERT_EQ(RunStudy(collect), 0);
  // runs.csv, summary.csv, the six plots and study.yaml (so the folder resumes as a whole run's
  // would): the same bytes as the study run whole.
  const std::map<std::string, std::string> whole = Files(Whole("")), collected = Files(out);
  EXPECT_EQ(whole.size(), 9u);
  ASSERT_EQ(collected.size(), whole.size());
  for (const auto& [name, text] : whole) {
    ASSERT_TRUE(collected.count(name)) << name;
    EXPECT_TRUE(collected.at(name) == text) << name << " differs";
  }
}

// 4 runs of one frame, no back end: cheap shards to break.
const char* const kTinyStudy = R"(name: tiny
frames: 1
seeds: 2
backend: false
sweep:
  distance: [1.5, 2.0]
)";

std::string CollectError(const StudyOptions& options, std::string* listed = nullptr) {
  ::testing::internal::CaptureStderr();
  std::string message = "no error";
  try {
    RunStudy(options);
  } catch (const InputError& e) {
    message = e.what();
  }
  const std::string err = ::testing::internal::GetCapturedStderr();
  if (listed) *listed = err;
  return message;
}

TEST(StudyShards, CollectNamesAShardMissingOrUnfinishedWithItsRunsAndWritesNothing) {
  TempDir dir;
  const std::string study = dir.Write("tiny.yaml", kTinyStudy), out = dir.File("out");
  StudyOptions shard = Options(study, out);
  shard.shard = "1/2";  // runs 0 and 3: 1, 2, then 2, 1
  ASSERT_EQ(RunStudy(shard), 0);
  StudyOptions collect = Options(study, out);
  collect.collect = true;
  std::string listed;
  std::string message = CollectError(collect, &listed);
  EXPECT_NE(message.find(out + ": cannot collect: 1 of 2 shards not finished (2/2 not started), 2 of 4 runs missing"),
            std::string::npos) << message;
  EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 0) << message;
  EXPECT_NE(listed.find("shard 2/2 (" + out + "/shards/2-of-2): not started"), std::string::npos) << listed;
  EXPECT_NE(listed.find("run 1 (distance 1.5 m, viewing angle 45 deg, noise x1, size x1, organized, seed 2)"),
            std::string::npos) << listed;
  EXPECT_NE(listed.find("run 2 (distance 2 m, viewing angle 45 deg, noise x1, size x1, organized, seed 1)"),
            std::string::npos) << listed;
  EXPECT_TRUE(Files(out).empty());  // no runs.csv, summary or plots of half a study

  // Half-finished: one run of two in, and half a line an interruption cut.
  shard.shard = "2/2";
  shard.max_runs = 1;
  ASSERT_EQ(RunStudy(shard), 0);
  std::ofstream(out + "/shards/2-of-2/runs.csv", std::ios::app) << "fig2,2,2,45,1,1,organized,1,track";
  message = CollectError(collect, &listed);
  EXPECT_NE(message.find("1 of 2 shards not finished (2/2 has 1 of 2 runs), 1 of 4 runs missing"), std::string::npos) << message;
  EXPECT_NE(listed.find("1 of its 2 runs finished; 1 run missing:\n    run 2 (distance 2 m"), std::string::npos) << listed;
  EXPECT_EQ(listed.find("run 1 ("), std::string::npos) << listed;
  EXPECT_TRUE(Files(out).empty());

  // The shard resumed to its end: collected.
  shard.max_runs = 0;
  ASSERT_EQ(RunStudy(shard), 0);
  ASSERT_EQ(RunStudy(collect), 0);
  EXPECT_EQ(RunIndices(out + "/runs.csv"), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_TRUE(fs::exists(out + "/summary.csv"));
}

TEST(StudyShards, CollectRefusesAShardOfOtherSettingsOrAnotherSplit) {
  TempDir dir;
  const std::string study = dir.Write("tiny.yaml", kTinyStudy), out = dir.File("out");
  for (const char* k : {"1/2", "2/2"}) {
    StudyOptions shard = Options(study, out);
    shard.shard = k;
    ASSERT_EQ(RunStudy(shard), 0);
  }
  // Collected with a study file of other settings: the first shard is refused, by its folder.
  std::string changed = kTinyStudy;
  changed.replace(changed.find("frames: 1"), 9, "frames: 2");
  StudyOptions other = Options(dir.Write("changed.yaml", changed), out);
  other.collect = true;
  EXPECT_NE(CollectError(other).find(out + "/shards/1-of-2: is a shard of a study with other settings"), std::string::npos);

  StudyOptions collect = Options(study, out);
  collect.collect = true;
  // A shard of the same study split 3 ways beside the 2-way split: which to collect is unclear.
  StudyOptions three = Options(study, out);
  three.shard = "1/3";
  ASSERT_EQ(RunStudy(three), 0);
  EXPECT_NE(CollectError(collect).find(out + "/shards: holds shards of the study split two ways (into 2: 1-of-2, 2-of-2; "
                                       "into 3: 1-of-3)"),
            std::string::npos);
  // ... or passed off as the 2-way split's first: its study.yaml says which it is.
  fs::remove_all(out + "/shards/1-of-2");
  fs::rename(out + "/shards/1-of-3", out + "/shards/1-of-2");
  EXPECT_NE(CollectError(collect).find(out + "/shards/1-of-2: is a shard of another split of this study"), std::string::npos);
  // A folder that is no shard's.
  fs::create_directories(out + "/shards/logs");
  EXPECT_NE(CollectError(collect).find(out + "/shards/logs: is no shard's folder (K-of-N)"), std::string::npos);
  fs::remove_all(out + "/shards");
  EXPECT_NE(CollectError(collect).find(out + "/shards: no shards to collect"), std::string::npos);
  EXPECT_TRUE(Files(out).empty());
}

TEST(StudyShards, ShardTextOtherThanKOfNAndOptionsThatClashAreErrorsBeforeAnyRun) {
  EXPECT_EQ(ParseStudyShard("3/8").k, 3);
  EXPECT_EQ(ParseStudyShard("3/8").n, 8);
  EXPECT_TRUE(ThrowsWith([] { ParseStudyShard("x"); }, {"--shard 'x': expected K/N"}));
  EXPECT_TRUE(ThrowsWith([] { ParseStudyShard("2/"); }, {"expected K/N"}));
  EXPECT_TRUE(ThrowsWith([] { ParseStudyShard("-1/4"); }, {"expected K/N"}));
  EXPECT_TRUE(ThrowsWith([] { ParseStudyShard("0/4"); }, {"--shard '0/4': K counts the shards from 1 to N (4)"}));
  EXPECT_TRUE(ThrowsWith([] { ParseStudyShard("5/4"); }, {"--shard '5/4': K counts the shards from 1 to N (4)"}));
  EXPECT_TRUE(ThrowsWith([] { ParseStudyShard("3/0"); }, {"--shard '3/0': N, the number of shards, must be 1 or more"}));
  EXPECT_TRUE(ThrowsWith([] { ParseStudyShard("99999999999/99999999999"); }, {"expected K/N"}));

  TempDir dir;
  const std::string study = dir.Write("tiny.yaml", kTinyStudy);
  StudyOptions options = Options(study, dir.File("out"));
  options.shard = "1/5";  // 4 runs
  EXPECT_TRUE(ThrowsWith([&] { RunStudy(options); }, {"has 4 runs, too few for 5 shards"}));
  options.report = dir.File("r.html");
  options.shard = "1/2";
  EXPECT_TRUE(ThrowsWith([&] { RunStudy(options); }, {"--report is the whole study's page: give it to --collect"}));
  options = Options(study, dir.File("out"));
  options.collect = true;
  options.shard = "1/2";
  EXPECT_TRUE(ThrowsWith([&] { RunStudy(options); }, {"--collect merges every shard: give it no --shard"}));
  options.shard = "";
  options.max_runs = 1;
  EXPECT_TRUE(ThrowsWith([&] { RunStudy(options); }, {"--collect runs nothing"}));
  EXPECT_FALSE(fs::exists(dir.File("out")));  // nothing ran, nothing was made
}

TEST(StudyShards, EveryRunGoesToOneShardAndEveryShardGetsAnEvenMixOfTheSweep) {
  // The default study's sweep: 5 distances x 3 noise levels x 2 segmenters x 4 seeds, 120 runs;
  // an MSAC run costs about 25 times an organized one.
  StudyConfig config;
  config.seeds = 4;
  config.sweep.distance = {1.0, 1.5, 2.0, 2.5, 3.0};
  config.sweep.noise = {0.5, 1.0, 2.0};
  config.sweep.segmenter = {"organized", "msac"};
  const std::vector<StudyRun> runs = StudyRuns(config);
  ASSERT_EQ(runs.size(), 120u);
  // The draft: 1 2 3 4, 4 3 2 1, 1 2 ...
  EXPECT_EQ(StudyShardOf(0, 4), 1);
  EXPECT_EQ(StudyShardOf(3, 4), 4);
  EXPECT_EQ(StudyShardOf(4, 4), 4);
  EXPECT_EQ(StudyShardOf(7, 4), 1);
  EXPECT_EQ(StudyShardOf(8, 4), 1);
  for (int n = 1; n <= 40; ++n) {
    SCOPED_TRACE(std::to_string(n) + " shards");
    std::vector<int> owner(runs.size(), 0);
    for (int k = 1; k <= n; ++k) {
      const std::vector<StudyRun> mine = ShardRuns(runs, {k, n});
      EXPECT_GE(mine.size(), runs.size() / n);  // the same number of runs, give or take one
      EXPECT_LE(mine.size(), (runs.size() + n - 1) / n);
      for (const StudyRun& run : mine) ++owner[run.index];
      EXPECT_EQ(StudyShardName({k, n}), std::to_string(k) + "-of-" + std::to_string(n));
      if (n > 16) continue;  // shards of 7 runs and more:
      // The slow MSAC runs spread evenly: each shard has its share of the 60, give or take two
      // (dealt round robin, 8 shards would have 0 or 15).
      const double msac = std::count_if(mine.begin(), mine.end(), [](const StudyRun& r) { return r.segmenter == "msac"; });
      EXPECT_NEAR(msac, 60.0 / n, 2.0) << "shard " << k;
      if (n == 8) {
        EXPECT_TRUE(msac == 7 || msac == 8) << msac;
      }
      // One run of every block of n neighbours: every distance, whose 24 runs hold a whole block
      // up to 12 shards.
      for (double d : config.sweep.distance) {
        if (n > 12) break;
        EXPECT_TRUE(std::any_of(mine.begin(), mine.end(), [&](const StudyRun& r) { return r.distance == d; })) << k << " " << d;
      }
    }
    EXPECT_EQ(std::count(owner.begin(), owner.end(), 1), static_cast<long>(runs.size()));  // each run once
  }
}

TEST(StudyShards, ACollectedStudysReportIsTheWholeStudysReport) {
  if (!fs::exists(SourcePath("web/node_modules/three/build/three.core.js"))) {
    GTEST_SKIP() << "web/node_modules missing: run scripts/setup.sh";
  }
  TempDir dir;
  const std::string study = dir.Write("tiny.yaml", kTinyStudy);
  StudyOptions whole = Options(study, dir.File("whole"));
  whole.report = dir.File("whole.html");
  ASSERT_EQ(RunStudy(whole), 0);
  for (const char* k : {"2/2", "1/2"}) {
    StudyOptions shard = Options(study, dir.File("sharded"));
    shard.shard = k;
    ASSERT_EQ(RunStudy(shard), 0);
  }
  StudyOptions collect = Options(study, dir.File("sharded"));
  collect.collect = true;
  collect.report = dir.File("sharded.html");
  ASSERT_EQ(RunStudy(collect), 0);
  const std::string page = ReadFile(dir.File("whole.html"));
  EXPECT_NE(page.find("planemap study tiny"), std::string::npos);
  EXPECT_TRUE(ReadFile(dir.File("sharded.html")) == page);
  EXPECT_EQ(Files(dir.File("sharded")), Files(dir.File("whole")));  // with run0_map.json
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
