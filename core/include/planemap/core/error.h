#pragma once
// Errors at the file and config boundary. Algorithms return result structs instead (STYLE.md).
#include <stdexcept>
#include <string>

namespace planemap {

// Thrown for bad input at the boundary: a missing or corrupt file, a malformed line, a bad key.
// The message always names where the problem is: "<file>:<line>: <what is wrong>".
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "<file>:<line>: <message>"; line <= 0 leaves the line out.
[[noreturn]] void ThrowInputError(const std::string& file, int line, const std::string& message);

}  // namespace planemap
