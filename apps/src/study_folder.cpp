#include "study_folder.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

#include "app_report.h"
#include "planemap/apps/app_config.h"
#include "planemap/core/error.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

// "K-of-N" with 1 <= K <= N, else false.
bool ParseShardName(const std::string& name, StudyShard* shard) {
  std::smatch m;
  if (!std::regex_match(name, m, std::regex("([0-9]{1,9})-of-([0-9]{1,9})"))) return false;
  *shard = {std::stoi(m[1]), std::stoi(m[2])};
  return shard->k >= 1 && shard->k <= shard->n;
}

std::string Describe(const StudyRun& run) {
  return Printf("run %d (distance %g m, viewing angle %g deg, noise x%g, size x%g, %s, seed %d)", run.index, run.distance,
                run.viewing_angle_deg, run.noise, run.object_scale, run.segmenter.c_str(), run.seed);
}

std::string Join(const std::vector<std::string>& items, const std::string& separator) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : separator) + item;
  return text;
}

// The shards' count, from their folders' names in `shards`: one count, or an InputError.
int ShardCount(const fs::path& shards, const std::string& again) {
  std::map<int, std::vector<std::string>> by_count;  // N -> its folders
  for (const fs::directory_entry& entry : fs::directory_iterator(shards)) {
    const std::string name = entry.path().filename().string();
    StudyShard shard;
    if (!entry.is_directory() || !ParseShardName(name, &shard)) {
      ThrowInputError(entry.path().string(), 0, "is no shard's folder (K-of-N): move it out of shards/ to collect");
    }
    by_count[shard.n].push_back(name);
  }
  if (by_count.empty()) ThrowInputError(shards.string(), 0, "holds no shards: run them first (" + again + ")");
  if (by_count.size() > 1) {
    std::vector<std::string> splits;
    for (auto& [n, names] : by_count) {
      std::sort(names.begin(), names.end());  // as listed, not as the file system happens to list them
      splits.push_back("into " + std::to_string(n) + ": " + Join(names, ", "));
    }
    ThrowInputError(shards.string(), 0,
                    "holds shards of the study split two ways (" + Join(splits, "; ") +
                        "); one study is one split: remove the other split's folders");
  }
  return by_count.begin()->first;
}

}  // namespace

// --- shards (apps/study.h) ----------------------------------------------------------------------

StudyShard ParseStudyShard(const std::string& text) {
  std::smatch m;
  if (!std::regex_match(text, m, std::regex("([0-9]{1,9})/([0-9]{1,9})"))) {
    throw InputError("--shard '" + text + "': expected K/N, shard K of N (e.g. --shard 2/8)");
  }
  const StudyShard shard{std::stoi(m[1]), std::stoi(m[2])};
  if (shard.n < 1) throw InputError("--shard '" + text + "': N, the number of shards, must be 1 or more");
  if (shard.k < 1 || shard.k > shard.n) {
    throw InputError("--shard '" + text + "': K counts the shards from 1 to N (" + std::to_string(shard.n) + ")");
  }
  return shard;
}

int StudyShardOf(int index, int n) {
  const int place = index % n;  // in its block of n neighbours
  return ((index / n) % 2 == 0 ? place : n - 1 - place) + 1;  // odd blocks dealt back
}

std::vector<StudyRun> ShardRuns(const std::vector<StudyRun>& runs, const StudyShard& shard) {
  std::vector<StudyRun> mine;
  for (const StudyRun& run : runs) {
    if (StudyShardOf(run.index, shard.n) == shard.k) mine.push_back(run);
  }
  return mine;
}

std::string StudyShardName(const StudyShard& shard) { return std::to_string(shard.k) + "-of-" + std::to_string(shard.n); }

// --- the folder ---------------------------------------------------------------------------------

std::string StudyIdentity(const StudyConfig& study) {
  std::ostringstream id;
  id << "# planemap study: the settings this folder's runs.csv was made with\n" << ConfigToYaml(study) << "\n";
  for (const std::string& file : {study.config, study.scene, study.camera, study.patterns}) {
    id << "---\n# " << file << "\n" << ReadText(ResolveConfigPath(file)) << "\n";
  }
  return id.str();
}

std::string ShardIdentity(const StudyConfig& study, const StudyShard& shard) {
  return StudyIdentity(study) + "---\n# shard " + std::to_string(shard.k) + " of " + std::to_string(shard.n) +
         " (apps/study.h: StudyShardOf)\n";
}

std::map<int, FinishedRun> ReadFinishedRuns(const fs::path& csv, const std::vector<StudyRun>& runs, int stages,
                                            const StudyShard& shard, int* dropped) {
  std::map<int, FinishedRun> finished;
  *dropped = 0;
  std::ifstream in(csv, std::ios::binary);
  if (!in) return finished;
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream lines(text);
  std::string line;
  if (!std::getline(lines, line) || line != StudyCsvHeader()) {
    ThrowInputError(csv.string(), 1, "not a planemap study CSV (its header differs); use another --out or --restart");
  }
  size_t consumed = line.size() + 1;
  while (std::getline(lines, line)) {
    consumed += line.size() + 1;
    StudyRow row;
    const bool whole = consumed <= text.size();  // the last line ends with a newline
    if (!whole || !ParseStudyCsvLine(line, &row) || row.run.index < 0 || row.run.index >= static_cast<int>(runs.size())) {
      ++*dropped;
      continue;
    }
    const StudyRun& run = runs[row.run.index];
    if (StudyShardOf(run.index, shard.n) != shard.k || row.run.segmenter != run.segmenter || row.run.seed != run.seed ||
        row.run.distance != run.distance || row.run.viewing_angle_deg != run.viewing_angle_deg ||
        row.run.noise != run.noise || row.run.object_scale != run.object_scale) {
      ++*dropped;
      continue;
    }
    FinishedRun& f = finished[row.run.index];
    const int slot = row.stage == "tracking" ? 0 : 1;
    f.twice = f.twice || !f.lines[slot].empty();
    f.lines[slot] = line;
    f.rows[slot] = row;
    ++f.stages;
  }
  for (auto it = finished.begin(); it != finished.end();) {
    if (it->second.stages == stages && !it->second.twice) {
      ++it;
    } else {
      *dropped += it->second.stages;
      it = finished.erase(it);
    }
  }
  return finished;
}

std::map<int, FinishedRun> CollectShards(const fs::path& out, const std::string& study_file, const StudyConfig& study,
                                         const std::vector<StudyRun>& runs, int stages) {
  const fs::path shards = out / "shards";
  std::string again = "planemap study " + study_file + " --shard K/N --out " + out.string();
  std::error_code ec;
  if (!fs::is_directory(shards, ec)) {
    ThrowInputError(shards.string(), 0, "no shards to collect: run them first (" + again + ")");
  }
  const int n = ShardCount(shards, again);

  // Every shard of the split: made with this study's settings, and its finished runs. Shards
  // not finished are listed with the runs they lack before anything is written.
  std::map<int, FinishedRun> all;
  std::vector<std::string> unfinished;
  size_t missing = 0;
  for (int k = 1; k <= n; ++k) {
    const StudyShard shard{k, n};
    const fs::path folder = shards / StudyShardName(shard);
    const std::string name = std::to_string(k) + "/" + std::to_string(n);
    std::map<int, FinishedRun> finished;
    const bool started = fs::exists(folder, ec);
    if (started) {
      const fs::path identity_file = folder / "study.yaml";
      if (!fs::exists(identity_file, ec)) {
        ThrowInputError(folder.string(), 0, "has no study.yaml: no shard of planemap study");
      }
      const std::string identity = ReadText(identity_file.string());
      if (identity != ShardIdentity(study, shard)) {
        const bool same_study = identity.rfind(StudyIdentity(study), 0) == 0;
        ThrowInputError(folder.string(), 0,
                        same_study ? "is a shard of another split of this study (its study.yaml names another shard): "
                                     "remove it, or collect the split it belongs to"
                                   : "is a shard of a study with other settings (its study.yaml differs from " +
                                         study_file + "'s): remove it, or collect with that study's file");
      }
      int dropped = 0;
      finished = ReadFinishedRuns(folder / "runs.csv", runs, stages, shard, &dropped);
    }
    const std::vector<StudyRun> mine = ShardRuns(runs, shard);
    if (finished.size() < mine.size()) {
      const size_t lacks = mine.size() - finished.size();
      const std::string of = std::to_string(finished.size()) + " of ";
      const std::string total = std::to_string(mine.size());
      unfinished.push_back(name + (started ? " has " + of + total + " runs" : " not started"));
      const std::string state = started ? of + "its " + total + " runs finished" : "not started, no folder";
      std::fprintf(stderr, "  shard %s (%s): %s; %zu run%s missing:\n", name.c_str(), folder.string().c_str(), state.c_str(),
                   lacks, lacks == 1 ? "" : "s");
      size_t listed = 0;
      for (const StudyRun& run : mine) {
        if (finished.count(run.index)) continue;
        if (listed++ == 10) {
          std::fprintf(stderr, "    ... and %zu more\n", lacks - 10);
          break;
        }
        std::fprintf(stderr, "    %s\n", Describe(run).c_str());
      }
      missing += lacks;
    }
    all.merge(finished);
  }
  if (!unfinished.empty()) {
    // The command to run, for the one shard to run, or a pattern for several.
    const std::string shard = unfinished.size() == 1 ? unfinished.front().substr(0, unfinished.front().find(' ')) : "K/N";
    again = "planemap study " + study_file + " --shard " + shard + " --out " + out.string();
    ThrowInputError(out.string(), 0,
                    "cannot collect: " + std::to_string(unfinished.size()) + " of " + std::to_string(n) +
                        " shards not finished (" + Join(unfinished, "; ") + "), " + std::to_string(missing) + " of " +
                        std::to_string(runs.size()) + " runs missing (listed above); run or resume " +
                        (unfinished.size() == 1 ? "it" : "them") + " (" + again + "), then collect again");
  }
  return all;
}

}  // namespace planemap
