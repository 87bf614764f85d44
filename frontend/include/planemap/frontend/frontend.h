#pragma once
// The frontend, step by step (paper section 4.1, Fig. 1): one RGB-D frame -> FrameModel.
#include <string>

#include "planemap/core/config.h"
#include "planemap/core/frame_model.h"
#include "planemap/core/intrinsics.h"
#include "planemap/core/rgbd_frame.h"
#include "planemap/frontend/intersections.h"
#include "planemap/frontend/objects.h"
#include "planemap/frontend/organized_cloud.h"
#include "planemap/frontend/plane_graph.h"
#include "planemap/frontend/plane_segmenter.h"

namespace planemap {

struct FrontendConfig {
  CloudConfig cloud;
  SegmenterConfig segmentation;
  IntersectionConfig intersections;
  PlaneGraphConfig graph;
  ObjectConfig objects;

  template <class V>
  void VisitFields(V&& v) {
    v("cloud", cloud);
    v("segmentation", segmentation);
    v("intersections", intersections);
    v("graph", graph);
    v("objects", objects);
  }
};

class Frontend {
 public:
  // Throws std::invalid_argument for out-of-range settings or an unknown segmenter.
  Frontend(const CameraIntrinsics& camera, const FrontendConfig& config, PatternsConfig patterns);

  // Never throws for what a frame holds: an empty or partial model says why in `reason`.
  FrameModel Process(const RgbdFrame& frame) const;
  FrameModel Process(const Cloud& cloud) const;

 private:
  CameraIntrinsics camera_;
  FrontendConfig config_;
  PatternsConfig patterns_;
  std::unique_ptr<PlaneSegmenter> segmenter_;
};

}  // namespace planemap
