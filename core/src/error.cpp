#include "planemap/core/error.h"

namespace planemap {

void ThrowInputError(const std::string& file, int line, const std::string& message) {
  std::string where = file;
  if (line > 0) where += ":" + std::to_string(line);
  throw InputError(where + ": " + message);
}

}  // namespace planemap
