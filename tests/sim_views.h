#pragma once
// Simulated frames for frontend tests: viewpoints of the default scene and rendered frames with
// the true plane of every label in the camera frame.
#include <map>
#include <vector>

#include "planemap/core/intrinsics.h"
#include "planemap/core/rgbd_frame.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/virtual_camera.h"

namespace planemap::testing {

using planemap::LookAt;  // core/pose.h

// Viewpoints of the default scene's box at 1-3 m from which it shows three faces, two sides and
// its top, each with 1500+ pixels: from a grid of 5 distances x 5 bearings x 3 heights, the views
// whose exact render shows them.
std::vector<Pose3> BoxViewpoints();

// Viewpoints of the default scene's box at 1-3 m from which it shows two faces only, each with
// 1500+ pixels and every other face under 100 (fewer than a plane needs): its top and one side
// (+x or -y), from 0.7-1.3 m high in front of that side; or those two sides, from 0.12-0.18 m
// high (below its top, 0.25 m). From a grid as BoxViewpoints, kept by the exact render.
std::vector<Pose3> BoxTwoFaceViewpoints();

struct SimFrame {
  RgbdFrame frame;
  LabelImage labels;
  std::map<std::uint16_t, Plane> planes_camera;  // every surface's plane in the camera frame
};

// Renders the default scene from `T_world_camera` with the full noise model (seeded).
SimFrame RenderDefaultScene(const Pose3& T_world_camera, std::uint64_t seed, bool noise = true);

const sim::Scene& DefaultScene();
const CameraIntrinsics& XtionCamera();

}  // namespace planemap::testing
