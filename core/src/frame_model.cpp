#include "planemap/core/frame_model.h"

#include <algorithm>

namespace planemap {

int FrameModel::EdgeBetween(int a, int b) const {
  if (a > b) std::swap(a, b);
  for (size_t i = 0; i < edges.size(); ++i) {
    if (edges[i].plane_a == a && edges[i].plane_b == b) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace planemap
