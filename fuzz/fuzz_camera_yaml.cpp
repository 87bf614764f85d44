// --camera FILE of every command, and a sequence's camera.yaml: LoadCameraIntrinsics.
#include "fuzz_input.h"
#include "planemap/core/intrinsics.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  return planemap::fuzz::ReadAsFile(data, size, "camera.yaml",
                                    [](const std::string& file) { planemap::LoadCameraIntrinsics(file); });
}
