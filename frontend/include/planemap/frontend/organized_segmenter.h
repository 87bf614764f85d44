#pragma once
#include "planemap/frontend/plane_segmenter.h"

namespace planemap {

// Cell-wise plane fits merged by region growing on the image grid (in the spirit of fast
// organized extractors such as PEAC and CAPE), then pixel assignment and a least-squares refit;
// the pixels no plane took are searched by sample consensus for faces too thin for a cell.
class OrganizedSegmenter : public PlaneSegmenter {
 public:
  explicit OrganizedSegmenter(const SegmenterConfig& config) : config_(config) {}
  SegmentationResult Segment(const Cloud& cloud) const override;

 private:
  SegmenterConfig config_;
};

}  // namespace planemap
