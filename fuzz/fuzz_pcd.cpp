// planemap frame --pcd FILE: an organized PCD cloud (LoadOrganizedPcd), here of an 8x6 camera so
// that small inputs are whole clouds (the seeds: fuzz/make_seeds.py).
#include "fuzz_input.h"
#include "planemap/frontend/pcd_source.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const planemap::CameraIntrinsics camera = planemap::fuzz::SmallCamera(8, 6);
  return planemap::fuzz::ReadAsFile(data, size, "cloud.pcd", [&](const std::string& file) {
    planemap::LoadOrganizedPcd(file, camera);
  });
}
