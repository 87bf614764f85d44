#include "planemap/apps/app_config.h"

#include <filesystem>

namespace planemap {

std::string ResolveConfigPath(const std::string& path) {
  namespace fs = std::filesystem;
  if (fs::exists(path)) return path;
  const std::string prefix = "configs/";
  if (path.rfind(prefix, 0) == 0) {
    const fs::path shipped = fs::path(PLANEMAP_SOURCE_DIR) / path;
    if (fs::exists(shipped)) return shipped.string();
  }
  return path;
}

}  // namespace planemap
