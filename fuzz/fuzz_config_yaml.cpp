// --config FILE of every command (configs/default.yaml): LoadConfigFile<AppConfig>.
#include "fuzz_input.h"
#include "planemap/apps/app_config.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  return planemap::fuzz::ReadAsFile(data, size, "config.yaml", [](const std::string& file) {
    planemap::LoadConfigFile<planemap::AppConfig>(file);
  });
}
