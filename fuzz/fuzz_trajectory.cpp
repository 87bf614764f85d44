// Trajectories in the TUM format: a sequence's groundtruth.txt (TumSequence::Open), planemap eval's
// --groundtruth and --estimate, planemap render's --trajectory when not a walk (.yaml). All read
// with ReadTumTrajectory.
#include "fuzz_input.h"
#include "planemap/core/tum_format.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  return planemap::fuzz::ReadAsFile(data, size, "groundtruth.txt",
                                    [](const std::string& file) { planemap::ReadTumTrajectory(file); });
}
