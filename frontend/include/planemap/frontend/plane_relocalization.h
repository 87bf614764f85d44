#pragma once
// Pose hypotheses from plane correspondences found without a predicted pose: frames far apart in
// time (a keyframe log, a dropped second, a robot that turned while the camera was off) and the
// recovery of a lost track. The paper's pose from plane correspondences (sec. 4.2) needs no
// prediction once the correspondences are known; here they are searched for:
//   1. rotation: the angle between two planes' normals does not depend on the pose, so a pair of
//      non-parallel frame planes can only be a pair of map planes at the same angle; each such
//      match gives a rotation (two normals fix it), scored by how many frame normals it lays on a
//      map normal (weighted);
//   2. translation: with the rotation fixed, every frame plane placed on a parallel map plane is
//      one linear constraint n . t = b on the translation; RANSAC over three of them with
//      normals spanning 3-D, the inliers also asked to overlap the map plane's extent;
//   3. the poses whose planes agree with the most map planes are returned, best first.
// Frames: source s (the camera), target t (the world); poses are T_target_source.
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/plane.h"
#include "planemap/core/pose.h"

namespace planemap {

struct RelocalizationConfig {
  int max_source_planes = 10;           // the largest frame planes form the rotation hypotheses
  int max_target_planes = 40;           // ... matched with the map's planes seen most
  double min_pair_angle_deg = 25.0;     // a pair's normals at least this far apart: nearer, a rotation from them is ill-posed [deg]
  double pair_angle_tolerance_deg = 4.0;  // a frame pair matches a map pair when their angles differ by less [deg]
  double inlier_angle_deg = 3.0;        // a placed frame normal within this of a map normal agrees with it [deg]
  double inlier_distance = 0.05;        // ... and its patch's centroid this close to the map plane [m]
  double overlap_margin = 0.30;         // ... and its placed extent within this of the map plane's [m]
  double rotation_merge_deg = 2.0;      // rotation hypotheses closer than this are one [deg]
  int max_rotations = 24;               // the best-supported rotations go on to the translation step
  int translation_samples = 60;         // triples of translation constraints tried per rotation
  double min_normal_spread = 0.2;       // a triple's normals must span 3-D this well (see SolvePlaneToPlane)
  int max_hypotheses = 4;               // poses returned

  int seed = 1;                         // of the sampler (std::mt19937_64): same seed, same result

  template <class V>
  void VisitFields(V&& v) {
    v("max_source_planes", max_source_planes, Check::kPositive);
    v("max_target_planes", max_target_planes, Check::kPositive);
    v("min_pair_angle_deg", min_pair_angle_deg, Check::kPositive);
    v("pair_angle_tolerance_deg", pair_angle_tolerance_deg, Check::kPositive);
    v("inlier_angle_deg", inlier_angle_deg, Check::kPositive);
    v("inlier_distance", inlier_distance, Check::kPositive);
    v("overlap_margin", overlap_margin, Check::kNonNegative);
    v("rotation_merge_deg", rotation_merge_deg, Check::kPositive);
    v("max_rotations", max_rotations, Check::kPositive);
    v("translation_samples", translation_samples, Check::kPositive);
    v("min_normal_spread", min_normal_spread, Check::kPositive);
    v("max_hypotheses", max_hypotheses, Check::kPositive);

    v("seed", seed, Check::kNonNegative);
  }
};

// A plane of either side: its equation, a point of its patch (the inliers' centroid), the patch's
// axis-aligned extent, and its weight in the support (e.g. its precision).
struct RelocalizationPlane {
  Plane plane;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // [m]
  Box3 extent;                                         // [m]
  double weight = 1.0;                                 // > 0
};

struct RelocalizationHypothesis {
  Pose3 T_target_source = Pose3::Identity();
  double support = 0.0;  // sum of the weights of the source planes it lays on a target plane
  int planes = 0;        // how many source planes that is
};

// Up to max_hypotheses poses, best supported first, each fixing all 6 degrees of freedom (its
// agreeing planes' normals span 3-D); none when no three non-parallel frame planes match map
// planes. `source` in the camera frame, `target` in the world. The caller decides which to trust
// (e.g. by its consensus over all candidate pairs, as the tracker's RANSAC does).
std::vector<RelocalizationHypothesis> RelocalizeByPlanes(const std::vector<RelocalizationPlane>& source,
                                                         const std::vector<RelocalizationPlane>& target,
                                                         const RelocalizationConfig& config);

}  // namespace planemap
