// planemap rooms --generator FILE (configs/rooms/default.yaml): LoadConfigFile<RoomGeneratorConfig>,
// as RunRooms reads it.
#include "fuzz_input.h"
#include "planemap/apps/rooms.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  return planemap::fuzz::ReadAsFile(data, size, "rooms.yaml", [](const std::string& file) {
    planemap::LoadConfigFile<planemap::RoomGeneratorConfig>(file);
  });
}
