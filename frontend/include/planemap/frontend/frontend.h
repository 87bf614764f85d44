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

  // Process's stages after the planes, one by one (bench_frontend times each): 3. the floor and
  // walls, then the real intersections, eqs. (2)-(6), on a model holding the planes; 4-5. the plane
  // graph, trihedral angles and objects, then their sizes, centres (eq. 7), grasp sides and class.
  void FindEdges(const Cloud& cloud, FrameModel* model) const;
  void FindObjects(const Cloud& cloud, FrameModel* model) const;

 private:
  // The floor's normal, or the configured prior when no floor was found.
  Eigen::Vector3d Up(const FrameModel& model) const;

  CameraIntrinsics camera_;
  FrontendConfig config_;
  PatternsConfig patterns_;
  std::unique_ptr<PlaneSegmenter> segmenter_;
};

}  // namespace planemap
