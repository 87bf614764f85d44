#pragma once
// What a study's folder holds, shared by `planemap study` run whole, run as one shard, and
// --collect: the settings its runs were made with (study.yaml) and the finished runs read back
// from its runs.csv.
//   OUT/study.yaml, runs.csv, summary.csv, *.svg     the whole study (run whole, or collected)
//   OUT/shards/K-of-N/study.yaml, runs.csv           shard K of N (--shard K/N)
#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "planemap/apps/study.h"

namespace planemap {

// What decides a study's rows: its settings and the text of every file it reads. A folder made
// with other settings is neither resumed into nor collected.
std::string StudyIdentity(const StudyConfig& study);
// A shard's: the study's, and which shard of how many.
std::string ShardIdentity(const StudyConfig& study, const StudyShard& shard);

// A finished run as read back: its rows (and their lines) by stage, tracking first.
struct FinishedRun {
  std::array<std::string, 2> lines;
  std::array<StudyRow, 2> rows;
  int stages = 0;      // rows read
  bool twice = false;  // a stage came twice: not a run this tool wrote
};

// The finished runs in `csv` (none when it does not exist), by run index. A line that is not a
// whole row of this study's runs in `shard` (cut by an interruption, of another sweep or shard)
// is dropped and counted in `dropped`, and so is a run missing one of its `stages`: it runs
// again. A file with another header is an InputError naming it.
std::map<int, FinishedRun> ReadFinishedRuns(const std::filesystem::path& csv, const std::vector<StudyRun>& runs,
                                            int stages, const StudyShard& shard, int* dropped);

// --collect: the finished runs of every shard in `out`/shards, all of the study's `runs`. The
// shards' count N is their folders' (K-of-N); a folder of another name, shards of two counts,
// or a shard of other settings is an InputError naming the folder. A shard missing or not
// finished is named with the runs it lacks (on stderr, then an InputError): nothing is collected.
std::map<int, FinishedRun> CollectShards(const std::filesystem::path& out, const std::string& study_file,
                                         const StudyConfig& study, const std::vector<StudyRun>& runs, int stages);

}  // namespace planemap
