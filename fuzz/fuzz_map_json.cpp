// A map.json: planemap merge's two maps and planemap eval --map, both read with ReadPlaneMapJson.
#include "fuzz_input.h"
#include "planemap/io/plane_map_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  return planemap::fuzz::ReadAsFile(data, size, "map.json", [](const std::string& file) { planemap::ReadPlaneMapJson(file); });
}
