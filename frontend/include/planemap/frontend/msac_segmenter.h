#pragma once
#include "planemap/frontend/plane_segmenter.h"

namespace planemap {

// The paper's reference: PCL's SAC_MSAC plane extraction, one plane after another.
class MsacSegmenter : public PlaneSegmenter {
 public:
  explicit MsacSegmenter(const SegmenterConfig& config) : config_(config) {}
  SegmentationResult Segment(const Cloud& cloud) const override;

 private:
  SegmenterConfig config_;
};

// Splits pixels into 8-connected parts on a width x height grid; parts are listed in the order
// of their first pixel, pixels in increasing index.
std::vector<std::vector<int>> ConnectedParts(const std::vector<int>& pixels, int width, int height);

}  // namespace planemap
