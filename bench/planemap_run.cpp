#include "planemap_run.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "planemap/core/error.h"

extern char** environ;

namespace fs = std::filesystem;

namespace planemap {
namespace {

constexpr size_t kStderrLines = 2;  // of a failed run's stderr, shown in its row

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  return fields;
}

double ParseNumber(const std::string& text, const std::string& file, int line, const std::string& column) {
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  ThrowInputError(file, line, "column " + column + ": '" + text + "' is not a number");
}

std::string ReadWholeFile(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// What a failed run's stderr says: its error lines, else its last lines (the progress lines,
// "\r"-updated, are lines too).
std::string ErrorLines(std::string text, size_t count) {
  std::replace(text.begin(), text.end(), '\r', '\n');
  std::vector<std::string> lines, errors;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    lines.push_back(line.substr(0, line.find_last_not_of(" \t") + 1));
    if (line.find("error") != std::string::npos) errors.push_back(lines.back());
  }
  const std::vector<std::string>& shown = errors.empty() ? lines : errors;
  std::string tail;
  for (size_t i = shown.size() > count ? shown.size() - count : 0; i < shown.size(); ++i)
    tail += (tail.empty() ? "" : " | ") + shown[i];
  return tail.empty() ? "(nothing on stderr)" : tail;
}

// The first line of `text` holding `word`, or "" .
std::string LineWith(const std::string& text, const std::string& word) {
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.find(word) != std::string::npos) return line;
  }
  return "";
}

// Runs argv with stdout and stderr into files; returns the exit code, -1 when it could not start,
// 128 + the signal when a signal ended it (as a shell reports it).
int Spawn(const std::vector<std::string>& args, const fs::path& stdout_file, const fs::path& stderr_file) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, stdout_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, stderr_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return WEXITSTATUS(status);
}

}  // namespace

std::vector<TrackingLogRow> ReadTrackingLog(const std::string& file) {
  std::ifstream in = OpenInputFile(file);
  std::string line;
  if (!std::getline(in, line)) ThrowInputError(file, 1, "no header");
  std::map<std::string, size_t> column;
  const std::vector<std::string> header = SplitCsvLine(line);
  for (size_t k = 0; k < header.size(); ++k) column[header[k]] = k;
  for (const char* name : {"status", "frontend_ms", "tracking_ms", "window_ms"}) {
    if (!column.count(name)) ThrowInputError(file, 1, std::string("no column ") + name + " in the header");
  }
  std::vector<TrackingLogRow> rows;
  for (int number = 2; std::getline(in, line); ++number) {
    const std::vector<std::string> f = SplitCsvLine(line);
    if (f.size() < header.size() - 1) ThrowInputError(file, number, "fewer fields than the header names");
    TrackingLogRow row;
    row.status = f[column["status"]];
    row.frontend_ms = ParseNumber(f[column["frontend_ms"]], file, number, "frontend_ms");
    row.tracking_ms = ParseNumber(f[column["tracking_ms"]], file, number, "tracking_ms");
    row.window_ms = ParseNumber(f[column["window_ms"]], file, number, "window_ms");
    rows.push_back(row);
  }
  return rows;
}

std::optional<double> RefineSeconds(const std::string& stdout_text) {
  static const std::regex kSolveLine(R"(refine: [^\n]*, [0-9]+ iterations, ([0-9.eE+-]+) s \()");
  std::smatch match;
  if (!std::regex_search(stdout_text, match, kSolveLine)) return std::nullopt;
  return std::stod(match[1].str());
}

PlanemapRun RunPlanemapMap(const std::string& binary, const std::string& sequence, const std::string& camera,
                           int stride, const std::string& out_dir) {
  PlanemapRun run;
  const fs::path out(out_dir);
  fs::create_directories(out);
  const fs::path stdout_file = out / "stdout.txt", stderr_file = out / "stderr.txt";
  run.exit_code = Spawn({binary, "map", sequence, "--camera", camera, "--stride", std::to_string(stride),
                         "--refine", "--out", out_dir},
                        stdout_file, stderr_file);
  if (run.exit_code == -1) {
    run.error = "cannot start " + binary;
    return run;
  }
  if (run.exit_code != 0) {
    run.error = ErrorLines(ReadWholeFile(stderr_file), kStderrLines);
    return run;
  }
  run.log = ReadTrackingLog((out / "tracking.csv").string());
  run.tracking = ReadTumTrajectory((out / "trajectory.txt").string());
  run.smoothed = ReadTumTrajectory((out / "trajectory_smoothed.txt").string());
  if (fs::exists(out / "trajectory_refined.txt")) {
    run.refined = ReadTumTrajectory((out / "trajectory_refined.txt").string());
  } else {
    run.refine_failure = "no trajectory_refined.txt: " + LineWith(ReadWholeFile(stderr_file), "back end");
  }
  run.refine_seconds = RefineSeconds(ReadWholeFile(stdout_file));
  return run;
}

}  // namespace planemap
