// --scene FILE of render, approach, nees, eval and rooms --scenes (configs/scenes/): sim::LoadScene.
#include "fuzz_input.h"
#include "planemap/sim/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  return planemap::fuzz::ReadAsFile(data, size, "scene.yaml", [](const std::string& file) { planemap::sim::LoadScene(file); });
}
