// A sequence's 16-bit depth PNG (TumSequence::LoadFrame, planemap frame --depth): ReadDepthPng,
// here of a 16x12 camera so that small inputs are whole images (the seeds: fuzz/make_seeds.py).
#include "fuzz_input.h"
#include "planemap/io/image_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const planemap::CameraIntrinsics camera = planemap::fuzz::SmallCamera(16, 12);
  return planemap::fuzz::ReadAsFile(data, size, "depth.png", [&](const std::string& file) {
    planemap::ReadDepthPng(file, camera, "depth.txt:3");
  });
}
