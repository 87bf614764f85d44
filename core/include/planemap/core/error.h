#pragma once
// Errors at the file and config boundary. Algorithms return result structs instead (STYLE.md).
#include <fstream>
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

// Opens `file` for reading; throws InputError naming it when it is missing, unreadable or a
// directory (std::ifstream opens a directory, then fails on the first read with a message that
// names no file).
std::ifstream OpenInputFile(const std::string& file, std::ios::openmode mode = std::ios::in);

// Throws InputError naming `file` when it could not be written (a folder of that name, a missing
// or read-only folder), so that a command fails before its work rather than after it. Leaves an
// existing file as it was and creates none. `what` names the output in the message ("the report":
// "cannot write the report ...").
void CheckWritableFile(const std::string& file, const std::string& what = "");

}  // namespace planemap
