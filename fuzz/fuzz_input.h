#pragma once
// What every fuzz target shares. The readers take paths, as the tool gives them, so the input is
// written to a file first (in /dev/shm, memory, when there is one). A reader may then succeed or
// throw InputError, the one-line error naming the file that main() prints; any other exception,
// a crash, a hang, a leak or an allocation over the limit is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "planemap/core/error.h"
#include "planemap/core/intrinsics.h"

namespace planemap::fuzz {

class InputFile {
 public:
  // `name` ends the file's name ("depth.png"), for readers that look at the extension.
  InputFile(const std::uint8_t* data, size_t size, const std::string& name)
      : path_(Folder() + "/planemap-fuzz-" + std::to_string(getpid()) + "-" + name) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (f == nullptr || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
      std::perror(path_.c_str());
      std::abort();
    }
  }
  ~InputFile() { std::remove(path_.c_str()); }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  const std::string& path() const { return path_; }

 private:
  static std::string Folder() { return access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp"; }
  std::string path_;
};

// Runs `read` on the input written to a file. An InputError is a correct answer to a bad file
// when its message names the file (`names_input`; a study's error may name the scene file it
// refers to instead); one that does not is a finding too.
template <class Read>
int ReadAsFile(const std::uint8_t* data, size_t size, const std::string& name, Read&& read, bool names_input = true) {
  const InputFile file(data, size, name);
  try {
    read(file.path());
  } catch (const InputError& e) {
    if (names_input && std::string(e.what()).find(file.path()) == std::string::npos) {
      std::fprintf(stderr, "fuzz: the error does not name the file %s: %s\n", file.path().c_str(), e.what());
      std::abort();
    }
  }
  return 0;
}

// The TUM default camera at width x height pixels (principal point in the middle): a whole image
// or cloud of it is an input of a few hundred bytes, as the seeds (make_seeds.py) are.
inline CameraIntrinsics SmallCamera(int width, int height) {
  CameraIntrinsics camera;
  camera.width = width;
  camera.height = height;
  camera.cx = 0.5 * (width - 1);
  camera.cy = 0.5 * (height - 1);
  return camera;
}

}  // namespace planemap::fuzz
