// planemap frame --pcd FILE: an organized PCD cloud (LoadOrganizedPcd), here of an 8x6 camera so
// that small inputs are whole clouds (the seeds: fuzz/make_seeds.py).
#include <pcl/console/print.h>

#include "fuzz_input.h"
#include "planemap/frontend/pcd_source.h"

// PCL's reader prints a line or two on stderr for each bad file (22 MB of log in 30 s); the
// reader's own error is what counts.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const planemap::CameraIntrinsics camera = planemap::fuzz::SmallCamera(8, 6);
  return planemap::fuzz::ReadAsFile(data, size, "cloud.pcd", [&](const std::string& file) {
    planemap::LoadOrganizedPcd(file, camera);
  });
}
