// rgb.txt, depth.txt and label.txt of a TUM-layout sequence: TumSequence::Open reads each with
// ReadFileList.
#include "fuzz_input.h"
#include "planemap/core/tum_format.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  return planemap::fuzz::ReadAsFile(data, size, "depth.txt", [](const std::string& file) { planemap::ReadFileList(file); });
}
