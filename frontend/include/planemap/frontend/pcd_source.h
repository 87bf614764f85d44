#pragma once
// Organized PCD clouds (e.g. the OSD / mOSD boxes) as a frame source.
#include <cstdint>
#include <string>
#include <vector>

#include "planemap/core/image.h"
#include "planemap/core/intrinsics.h"
#include "planemap/frontend/organized_cloud.h"

namespace planemap {

struct PcdFrame {
  Cloud::Ptr cloud;                    // organized, camera frame, NaN where no point
  ColorImage color;
  std::vector<std::uint32_t> labels;   // the file's per-point label field, 0 when it has none
};

// Throws InputError naming the file when it cannot be read or is not an organized cloud of the
// camera's size.
PcdFrame LoadOrganizedPcd(const std::string& file, const CameraIntrinsics& camera);

}  // namespace planemap
