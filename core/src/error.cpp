#include "planemap/core/error.h"

#include <filesystem>

namespace planemap {

void ThrowInputError(const std::string& file, int line, const std::string& message) {
  std::string where = file;
  if (line > 0) where += ":" + std::to_string(line);
  throw InputError(where + ": " + message);
}

std::ifstream OpenInputFile(const std::string& file, std::ios::openmode mode) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) ThrowInputError(file, 0, "is a directory, not a file");
  std::ifstream in(file, mode);
  if (!in) ThrowInputError(file, 0, "cannot open file");
  return in;
}

void CheckWritableFile(const std::string& file, const std::string& what) {
  const std::string cannot = what.empty() ? "cannot write" : "cannot write " + what;
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) ThrowInputError(file, 0, cannot + ": a folder of that name exists");
  const bool existed = std::filesystem::exists(file, ec);
  {
    std::ofstream out(file, std::ios::app);  // opens without truncating an existing file
    if (!out) ThrowInputError(file, 0, cannot + " (does its folder exist, may it be written?)");
  }
  if (!existed) std::filesystem::remove(file, ec);
}

}  // namespace planemap
