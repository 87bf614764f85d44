// planemap study FILE (configs/studies/): LoadStudy, which also reads the scene and settings the
// study names (from configs/ when the fuzzer keeps their names) and checks every viewpoint. Its
// error may name those files rather than the study.
#include "fuzz_input.h"
#include "planemap/apps/study.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  return planemap::fuzz::ReadAsFile(
      data, size, "study.yaml", [](const std::string& file) { planemap::LoadStudy(file); }, /*names_input=*/false);
}
