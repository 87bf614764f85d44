// planemap rooms: the closed-loop approach over generated rooms (or given scene files), in
// parallel into a resumable CSV, then a summary that tallies the failures by reason.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include <omp.h>

#include "app_report.h"
#include "parallel_runs.h"
#include "planemap/apps/app_config.h"
#include "planemap/apps/approach.h"
#include "planemap/apps/commands.h"
#include "planemap/apps/rooms.h"
#include "planemap/core/error.h"
#include "planemap/core/statistics.h"
#include "planemap/sim/scene.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
// One approach run in one room, as runs.csv holds it.
struct RoomRun {
  int room = 0;               // 1-based, in the order of the rooms
  std::string scene;          // the scene file
  int seed = 0;
  int scenario = 0;
  bool success = false;       // reached, grasp check ok, no collision
  bool reached = false, grasp_ok = false, collided = false;
  std::string failure;        // the failure's class (FailureClass); empty on success
  double position_error = NAN;  // [m]; NaN when nothing was planned
  double heading_error = NAN;   // [rad]
  double time = 0.0;          // simulated [s]
  int frames = 0, lost_frames = 0, viewpoints = 0;
  std::string approached;     // the scene object approached
  std::string reason;         // how the run ended
};

const char* const kHeader =
    "room,scene,seed,scenario,success,reached,grasp_ok,collided,failure,pregrasp_position_error_cm,"
    "pregrasp_heading_error_deg,time_s,frames,lost_frames,viewpoints,approached,reason";

// What went wrong, as a class to tally: the first that applies.
std::string FailureClass(const ApproachRun& r) {
  if (r.Reached() && r.grasp_ok && !r.collided) return "";
  if (r.collided) return "collision";
  if (r.WrongObject()) return "approached another object";
  if (r.Reached()) return "grasp check failed at the pre-grasp pose";
  const std::string& why = r.status.reason;
  const auto has = [&](const char* s) { return why.find(s) != std::string::npos; };
  if (has("out of time")) return "out of time";
  if (has("no pose estimate")) return "tracking lost";
  if (!r.planned) {
    if (has("the arms can grasp")) return "box mapped, judged ungraspable";
    if (has("a plan reaches")) return "box mapped, no path to it";
    if (r.task_object_mapped == false) return "box never mapped";  // by the scene's truth
    if (has("of another size")) return "box mapped at another size";
    if (has("in the map")) return "box never mapped";
    if (has("looking again")) return "walk to a viewpoint failed";
    return "no plan";
  }
  if (has("re-plan")) return "re-planning failed";
  if (has("approach_steps_max")) return "approach did not converge";
  return "stopped on the way";
}

std::string Field(std::string text) {
  for (char& c : text) {
    if (c == ',') c = ';';
    if (c == '\n' || c == '\r') c = ' ';
  }
  return text;
}

std::string Number(double x, const char* format = "%.2f") { return std::isnan(x) ? "" : Printf(format, x); }

std::string CsvLine(const RoomRun& r) {
  return Printf("%d,%s,%d,%d,%d,%d,%d,%d,%s,%s,%s,%.1f,%d,%d,%d,%s,%s", r.room, Field(r.scene).c_str(), r.seed, r.scenario,
                r.success, r.reached, r.grasp_ok, r.collided, Field(r.failure).c_str(),
                Number(100.0 * r.position_error).c_str(), Number(kRadToDeg * r.heading_error).c_str(), r.time, r.frames,
                r.lost_frames, r.viewpoints, Field(r.approached).c_str(), Field(r.reason).c_str());
}

bool ParseCsvLine(const std::string& line, RoomRun* r) {
  std::vector<std::string> f;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) f.push_back(field);
  if (!line.empty() && line.back() == ',') f.emplace_back();
  if (f.size() != 17) return false;
  try {
    r->room = std::stoi(f[0]);
    r->scene = f[1];
    r->seed = std::stoi(f[2]);
    r->scenario = std::stoi(f[3]);
    r->success = f[4] == "1";
    r->reached = f[5] == "1";
    r->grasp_ok = f[6] == "1";
    r->collided = f[7] == "1";
    r->failure = f[8];
    r->position_error = f[9].empty() ? NAN : std::stod(f[9]) / 100.0;
    r->heading_error = f[10].empty() ? NAN : std::stod(f[10]) / kRadToDeg;
    r->time = std::stod(f[11]);
    r->frames = std::stoi(f[12]);
    r->lost_frames = std::stoi(f[13]);
    r->viewpoints = std::stoi(f[14]);
    r->approached = f[15];
    r->reason = f[16];
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

RoomRun Row(int room, const std::string& scene, const ApproachRun& a) {
  RoomRun r;
  r.room = room;
  r.scene = scene;
  r.seed = a.seed;
  r.scenario = a.scenario;
  r.reached = a.Reached();
  r.grasp_ok = a.grasp_ok;
  r.collided = a.collided;
  r.failure = FailureClass(a);
  r.success = r.failure.empty();
  if (a.planned) {
    r.position_error = a.position_error;
    r.heading_error = a.heading_error;
  }
  r.time = a.duration;
  r.frames = a.frames;
  r.lost_frames = a.lost_frames;
  r.viewpoints = static_cast<int>(a.viewpoints.size());
  r.approached = a.target;
  r.reason = a.status.reason + (a.collided ? "; collision: " + a.collision : "") +
             (a.Reached() && !a.grasp_ok ? "; grasp check: " + a.grasp_reason : "");
  return r;
}

// The summary: successes, their pre-grasp errors, the failures by class with the rooms they hit.
std::vector<std::string> SummaryLines(const RoomsOptions& o, const std::vector<RoomRun>& runs, size_t rooms) {
  std::vector<std::string> lines;
  std::vector<double> position, heading, time;
  std::map<std::string, std::vector<const RoomRun*>> failures;
  int success = 0, reached = 0, grasp_ok = 0, collided = 0;
  for (const RoomRun& r : runs) {
    success += r.success;
    reached += r.reached;
    grasp_ok += r.grasp_ok;
    collided += r.collided;
    if (r.success) {
      position.push_back(100.0 * r.position_error);
      heading.push_back(kRadToDeg * r.heading_error);
      time.push_back(r.time);
    } else {
      failures[r.failure].push_back(&r);
    }
  }
  const double n = static_cast<double>(std::max<size_t>(1, runs.size()));
  lines.push_back(Printf("planemap rooms: %zu runs: %zu %s, scenario %d, seed%s %d%s, %.0f Hz", runs.size(), rooms,
                         o.scenes.empty() ? Printf("rooms generated with seed %d", o.room_seed).c_str() : "scene files",
                         o.run.scenario, o.seeds > 1 ? "s" : "", o.run.seed,
                         o.seeds > 1 ? Printf("-%d", o.run.seed + o.seeds - 1).c_str() : "", o.run.rate));
  lines.push_back(Printf("  reached the pre-grasp pose with the grasp check ok and no collision: %d of %zu (%.0f%%)", success,
                         runs.size(), 100.0 * success / n));
  lines.push_back(Printf("  reached %d, grasp check ok %d, collided %d", reached, grasp_ok, collided));
  if (!position.empty()) {
    lines.push_back(Printf("  pre-grasp error of those: position median %.1f cm, 90%% %.1f cm, worst %.1f cm; heading median %.1f "
                           "deg, worst %.1f deg; time median %.0f s, worst %.0f s",
                           Percentile(position, 0.5), Percentile(position, 0.9), Percentile(position, 1.0),
                           Percentile(heading, 0.5), Percentile(heading, 1.0), Percentile(time, 0.5), Percentile(time, 1.0)));
  }
  if (!failures.empty()) {
    std::vector<std::pair<std::string, std::vector<const RoomRun*>>> sorted(failures.begin(), failures.end());
    std::stable_sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.second.size() > b.second.size(); });
    lines.push_back("  failures by reason (runs, share of all runs, rooms/seeds):");
    for (const auto& [name, list] : sorted) {
      std::string where;
      for (size_t k = 0; k < list.size() && k < 12; ++k) {
        where += (k ? ", " : "") + std::to_string(list[k]->room) + (o.seeds > 1 ? "/" + std::to_string(list[k]->seed) : "");
      }
      if (list.size() > 12) where += ", ...";
      lines.push_back(Printf("    %-42s %4zu %5.0f%%   %s", name.c_str(), list.size(), 100.0 * list.size() / n, where.c_str()));
    }
  }
  return lines;
}

std::string SummaryCsv(const std::vector<RoomRun>& runs) {
  std::map<std::string, int> counts;
  for (const RoomRun& r : runs) ++counts[r.success ? "success" : r.failure];
  std::string text = "outcome,runs,share\n";
  for (const auto& [name, count] : counts)
    text += Printf("%s,%d,%.4f\n", Field(name).c_str(), count, static_cast<double>(count) / std::max<size_t>(1, runs.size()));
  return text;
}

}  // namespace

int RunRooms(const RoomsOptions& options) {
  if (options.run.scenario < 1 || options.run.scenario > 3) throw InputError("--scenario must be 1, 2 or 3");
  if (options.count < 1 && options.scenes.empty()) throw InputError("--count must be 1 or more");
  if (options.seeds < 1) throw InputError("--seeds must be 1 or more");
  if (options.max_runs < 0) throw InputError("--max-runs must be 0 (all) or more");
  const fs::path out(options.out.empty() ? "out/rooms_" + std::to_string(options.room_seed) : options.out);
  std::error_code ec;
  fs::create_directories(out / "rooms", ec);
  if (ec) ThrowInputError(out.string(), 0, "cannot create folder: " + ec.message());

  // The rooms: scene files as given, or generated into <out>/rooms/.
  const AppConfig config = LoadConfigFile<AppConfig>(ResolveConfigPath(options.run.config));
  std::vector<std::string> scenes;
  std::ostringstream identity;
  identity << "# planemap rooms: the settings this folder's runs.csv was made with\n"
           << Printf("scenario: %d\nseed: %d\nseeds: %d\nrate: %.17g\nmax_time: %.17g\n", options.run.scenario, options.run.seed,
                     options.seeds, options.run.rate, options.run.max_time);
  if (options.scenes.empty()) {
    const std::string generator_file = ResolveConfigPath(options.generator);
    const RoomGeneratorConfig generator = LoadConfigFile<RoomGeneratorConfig>(generator_file);
    identity << "room_seed: " << options.room_seed << "\ncount: " << options.count << "\n---\n# " << options.generator << "\n"
             << ConfigToYaml(generator) << "\n";
    std::fprintf(stderr, "planemap rooms: generating %d rooms (seed %d) into %s\n", options.count, options.room_seed,
                 (out / "rooms").string().c_str());
    for (int k = 1; k <= options.count; ++k) {
      const GeneratedRoom room = GenerateRoom(generator, static_cast<std::uint64_t>(options.room_seed), k, config.planner,
                                              config.grasp, options.run.body_height);
      YAML::Emitter emitter;
      emitter << room.scene;
      const std::string file = (out / "rooms" / Printf("room_%03d.yaml", k)).string();
      WriteFileAtomically(file, Printf("# Generated by planemap rooms (seed %d, room %d): %s\n# The robot starts at the origin "
                                       "facing +x; its pre-grasp pose is reachable on the true geometry (path %.1f m).\n",
                                       options.room_seed, k, room.summary.c_str(), room.reach.path_length) +
                                    emitter.c_str() + "\n");
      scenes.push_back(file);
    }
  } else {
    for (const std::string& s : options.scenes) {
      const std::string file = ResolveConfigPath(s);
      sim::LoadScene(file);  // a bad file fails here, before any run
      scenes.push_back(file);
      identity << "---\n# " << s << "\n" << ReadText(file) << "\n";
    }
  }
  if (options.generate_only) {
    std::printf("planemap rooms: wrote %zu rooms to %s\n", scenes.size(), (out / "rooms").string().c_str());
    return 0;
  }
  for (const std::string& file : {options.run.config, options.run.camera, options.run.patterns}) {
    identity << "---\n# " << file << "\n" << ReadText(ResolveConfigPath(file)) << "\n";
  }
  const fs::path csv = out / "runs.csv", identity_file = out / "rooms.yaml";
  if (options.restart) {
    fs::remove(csv, ec);
  } else if (fs::exists(csv) && fs::exists(identity_file) && ReadText(identity_file.string()) != identity.str()) {
    ThrowInputError(out.string(), 0,
                    "holds the runs of other rooms or settings (its rooms.yaml differs): use another --out, or --restart to "
                    "discard them");
  }
  WriteFileAtomically(identity_file.string(), identity.str());

  // Every (room, seed); the finished ones of an interrupted invocation are kept.
  struct Job {
    int room;
    int seed;
  };
  std::vector<Job> jobs;
  for (int room = 1; room <= static_cast<int>(scenes.size()); ++room) {
    for (int s = 0; s < options.seeds; ++s) jobs.push_back({room, options.run.seed + s});
  }
  const auto key = [&](int room, int seed) { return (room - 1) * options.seeds + (seed - options.run.seed); };
  std::map<int, std::pair<RoomRun, std::string>> finished;
  int dropped = 0;
  const auto read_finished = [&] {
    finished.clear();
    dropped = 0;
    std::ifstream in(csv, std::ios::binary);
    if (!in) return;
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::istringstream lines(text);
    std::string line;
    if (!std::getline(lines, line) || line != kHeader)
      ThrowInputError(csv.string(), 1, "not a planemap rooms CSV (its header differs); use another --out or --restart");
    size_t consumed = line.size() + 1;
    while (std::getline(lines, line)) {
      consumed += line.size() + 1;
      RoomRun r;
      if (consumed > text.size() || !ParseCsvLine(line, &r) || r.room < 1 || r.room > static_cast<int>(scenes.size()) ||
          r.seed < options.run.seed || r.seed >= options.run.seed + options.seeds || r.scene != Field(scenes[r.room - 1])) {
        ++dropped;
        continue;
      }
      finished[key(r.room, r.seed)] = {r, line};
    }
  };
  read_finished();
  const size_t resumed = finished.size();
  {
    std::string text = std::string(kHeader) + "\n";
    for (const auto& [k, run] : finished) text += run.second + "\n";
    WriteFileAtomically(csv.string(), text);
  }
  std::vector<Job> pending;
  for (const Job& j : jobs) {
    if (!finished.count(key(j.room, j.seed))) pending.push_back(j);
  }
  if (options.max_runs > 0 && pending.size() > static_cast<size_t>(options.max_runs)) pending.resize(options.max_runs);
  const int threads = options.threads > 0 ? options.threads : omp_get_num_procs();
  std::fprintf(stderr, "planemap rooms: %zu runs (%zu rooms x %d seeds), %zu finished before%s, %zu to run on %d threads\n",
               jobs.size(), scenes.size(), options.seeds, resumed,
               dropped ? (", " + std::to_string(dropped) + " cut or foreign lines dropped").c_str() : "", pending.size(), threads);

  // Every run reads the files as they are now: an edit while the study runs changes nothing.
  std::vector<std::shared_ptr<const ApproachInputs>> inputs(scenes.size());
  for (const Job& j : pending) {
    if (inputs[j.room - 1]) continue;
    ApproachOptions o = options.run;
    o.scene = scenes[j.room - 1];
    inputs[j.room - 1] = LoadApproachInputs(o);
  }
  std::ofstream append(csv, std::ios::app | std::ios::binary);
  if (!append) ThrowInputError(csv.string(), 0, "cannot append");
  const ParallelRuns ran = RunInParallel(
      pending.size(), threads, resumed, jobs.size(), append,
      [&](size_t i) {
        ApproachOptions o = options.run;
        o.scene = scenes[pending[i].room - 1];
        o.seed = pending[i].seed;
        return CsvLine(Row(pending[i].room, o.scene, RunApproachOnce(o, *inputs[pending[i].room - 1]))) + "\n";
      },
      [&](size_t i) { return "room " + std::to_string(pending[i].room) + " (" + scenes[pending[i].room - 1] + ")"; });
  append.close();
  if (!append) ThrowInputError(csv.string(), 0, "write failed");
  read_finished();
  if (finished.size() < jobs.size()) {
    std::printf("planemap rooms: %zu of %zu runs in %s; run the same command again to resume\n", finished.size(), jobs.size(),
                csv.string().c_str());
    return ran.interrupted ? 130 : 0;
  }
  // Every run is in: the CSV in run order, whatever order they finished in, then the summary.
  std::string text = std::string(kHeader) + "\n";
  std::vector<RoomRun> rows;
  for (const auto& [k, run] : finished) {
    text += run.second + "\n";
    rows.push_back(run.first);
  }
  WriteFileAtomically(csv.string(), text);
  const std::vector<std::string> lines = SummaryLines(options, rows, scenes.size());
  std::string summary;
  for (const std::string& line : lines) {
    std::printf("%s\n", line.c_str());
    summary += line + "\n";
  }
  WriteFileAtomically((out / "summary.txt").string(), summary);
  WriteFileAtomically((out / "summary.csv").string(), SummaryCsv(rows));
  std::printf("  wrote %s, %s, %s\n", csv.string().c_str(), (out / "summary.txt").string().c_str(),
              (out / "summary.csv").string().c_str());
  return 0;
}

}  // namespace planemap
