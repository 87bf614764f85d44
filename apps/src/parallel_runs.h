#pragma once
// What `planemap study` and `planemap rooms` share: independent seeded runs in parallel, each
// finished run's rows appended to a CSV at once, so an interrupted sweep keeps every finished run.
#include <cstddef>
#include <fstream>
#include <functional>
#include <string>

namespace planemap {

struct ParallelRuns {
  size_t done = 0;           // runs finished and appended
  bool interrupted = false;  // Ctrl-C: the runs under way finished, no new one started
};

// Runs run(0) ... run(count - 1) on `threads` threads, one run per thread (the renderer's OpenMP
// loops get one thread each: runs side by side fill the cores), and appends each run's text to
// `append` as soon as it returns (whole runs only: an interruption cuts at most one write).
// Progress on stderr counts from `resumed` of `total`. The first run that throws stops new ones;
// after the others finish, its message, prefixed by name(i), is thrown as an InputError.
ParallelRuns RunInParallel(size_t count, int threads, size_t resumed, size_t total, std::ofstream& append,
                           const std::function<std::string(size_t)>& run, const std::function<std::string(size_t)>& name);

}  // namespace planemap
