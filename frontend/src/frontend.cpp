#include "planemap/frontend/frontend.h"

namespace planemap {

Frontend::Frontend(const CameraIntrinsics& camera, const FrontendConfig& config, PatternsConfig patterns)
    : camera_(camera), config_(config), patterns_(std::move(patterns)), segmenter_(MakePlaneSegmenter(config.segmentation)) {
  ValidateConfig(camera_, "camera.");
  ValidateConfig(config_, "frontend.");  // also up_in_camera: 3 numbers, not zero
}

FrameModel Frontend::Process(const RgbdFrame& frame) const {
  return Process(*MakeOrganizedCloud(frame, camera_, config_.cloud));
}

FrameModel Frontend::Process(const Cloud& cloud) const {
  FrameModel model;
  // 1-2. Planes (MSAC or organized), normals toward the camera.
  SegmentationResult segmentation = segmenter_->Segment(cloud);
  model.planes = std::move(segmentation.planes);
  if (model.planes.empty()) {
    model.reason = segmentation.reason;
    return model;
  }
  FindEdges(cloud, &model);
  FindObjects(cloud, &model);

  if (model.planes.size() < 3) {
    model.reason = std::to_string(model.planes.size()) + " plane(s): a trihedral angle needs three";
  } else if (model.edges.empty()) {
    model.reason = "no real intersection between the " + std::to_string(model.planes.size()) + " planes";
  } else if (model.angles.empty()) {
    model.reason = "no trihedral angle among " + std::to_string(model.edges.size()) + " intersections";
  } else if (model.objects.empty()) {
    model.reason = "trihedral angles only between room structure (floor, walls): no object";
  }
  return model;
}

void Frontend::FindEdges(const Cloud& cloud, FrameModel* model) const {
  // 3. Real intersections, eqs. (2)-(6); the floor and walls first, which end the edges that run
  //    into them.
  FindStructure(cloud, config_.graph, model);
  EdgeTerminators terminators;
  terminators.structure = model->structure;
  terminators.up = Up(*model);
  model->edges = FindIntersections(model->planes, cloud, camera_, config_.intersections, &terminators);
}

void Frontend::FindObjects(const Cloud& cloud, FrameModel* model) const {
  // 4. Plane graph, trihedral angles, objects aggregated angle by angle (the structure is known).
  FindFaces(cloud, config_.graph, model);
  AggregateObjects(cloud, config_.graph, model);
  // 5. Dimensions, centre (eq. 7), grasp sides and axis; then the class, which may use height.
  MeasureObjects(cloud, config_.objects, UpPrior(config_.graph), model);
  ClassifyObjects(patterns_, config_.objects, Up(*model), model);
}

Eigen::Vector3d Frontend::Up(const FrameModel& model) const {
  return model.floor >= 0 ? model.planes[model.floor].plane.normal : UpPrior(config_.graph);
}

}  // namespace planemap
