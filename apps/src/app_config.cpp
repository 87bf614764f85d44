#include "planemap/apps/app_config.h"

#include <filesystem>
#include <system_error>

namespace planemap {

namespace fs = std::filesystem;

std::string ShippedDataDir() {
  // An installed tool: <prefix>/bin/planemap reads <prefix>/share/planemap.
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path() / PLANEMAP_BIN_TO_DATA;
    if (fs::is_directory(installed / "configs", ec)) return fs::weakly_canonical(installed, ec).string();
  }
  return PLANEMAP_SOURCE_DIR;
}

std::string ResolveConfigPath(const std::string& path) {
  // The error_code forms: a path the system refuses (a name over 255 bytes: ENAMETOOLONG) is one
  // that does not exist here, and its reader says so naming it (fuzz_study_yaml: std::filesystem
  // threw filesystem_error from a study's config path, an error naming no input file).
  std::error_code ec;
  if (fs::exists(path, ec)) return path;
  const std::string prefix = "configs/";
  if (path.rfind(prefix, 0) == 0) {
    const fs::path shipped = fs::path(ShippedDataDir()) / path;
    if (fs::exists(shipped, ec)) return shipped.string();
  }
  return path;
}

}  // namespace planemap
