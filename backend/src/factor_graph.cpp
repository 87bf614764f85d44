#include "factor_graph.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "planemap/core/statistics.h"
#include "planemap/factors/box_contact_factor.h"
#include "planemap/factors/box_face_factor.h"
#include "planemap/factors/edge_length_factor.h"
#include "planemap/factors/object_center_factor.h"
#include "planemap/factors/plane_observation_factor.h"
#include "planemap/factors/relative_pose_factor.h"
#include "planemap/factors/structure_factor.h"

namespace planemap::backend_detail {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

ceres::LossFunction* MakeLoss(const RobustLossConfig& c) {
  if (c.type == "huber") return new ceres::HuberLoss(c.scale);
  if (c.type == "cauchy") return new ceres::CauchyLoss(c.scale);
  if (c.type == "soft_l1") return new ceres::SoftLOneLoss(c.scale);
  if (c.type == "none") return nullptr;
  throw std::invalid_argument("backend.loss.type must be huber, cauchy, soft_l1 or none, not '" + c.type + "'");
}

// Square-root information of a 6-dof pose error (translation, then rotation) with these sigmas.
Eigen::Matrix<double, 6, 6> SqrtInformation(double sigma, double sigma_rad) {
  Eigen::Matrix<double, 6, 1> d;
  d << Eigen::Vector3d::Constant(1.0 / sigma), Eigen::Vector3d::Constant(1.0 / sigma_rad);
  return d.asDiagonal();
}

// The box axis (index) most parallel to a world direction, and how closely (|cos|).
int NearestAxis(const Eigen::Matrix3d& R, const Eigen::Vector3d& direction, double* cosine) {
  const Eigen::Vector3d local = R.transpose() * direction;
  int k = 0;
  *cosine = local.cwiseAbs().maxCoeff(&k);
  return k;
}

// A rotation from an object's axes (columns x, y, z), made orthonormal and right-handed.
Eigen::Matrix3d Orthonormal(const Eigen::Matrix3d& axes) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(axes, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d R = svd.matrixU() * svd.matrixV().transpose();
  if (R.determinant() < 0.0) R.col(1) = -R.col(1);
  return R;
}

// Standard deviation of the direction R e_axis [deg] from the rotation's tangent covariance
// (world-frame rotation vector, as EigenQuaternionManifold's Plus): d(a) = dtheta x a.
double AxisStdDeg(const Eigen::Matrix3d& rotation_covariance, const Eigen::Vector3d& a) {
  Eigen::Matrix3d skew;
  skew << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return std::sqrt(std::max(0.0, (skew * rotation_covariance * skew.transpose()).trace())) / kDegToRad;
}

}  // namespace

ceres::LinearSolverType SolverType(const std::string& name) {
  if (name == "sparse_schur") return ceres::SPARSE_SCHUR;
  if (name == "sparse_normal_cholesky") return ceres::SPARSE_NORMAL_CHOLESKY;
  throw std::invalid_argument("backend.linear_solver must be sparse_schur or sparse_normal_cholesky, not '" + name + "'");
}

FactorGraph::FactorGraph(const PlaneMap& map, const std::vector<const FrameObservations*>& frames,
                         const std::vector<Pose3>& initial, const BackendConfig& config, const GraphSpec& spec)
    : map_(map), config_(config), spec_(spec) {
  SolverType(config.linear_solver);  // fails early on a bad name
  loss_.reset(MakeLoss(config.loss));
  pose_manifold_ = std::make_unique<PoseManifold>();
  plane_manifold_ = std::make_unique<PlaneManifold>();

  for (size_t i = 0; i < frames.size(); ++i) {
    poses_.push_back(ToBlock(initial[i]));
    problem_.AddParameterBlock(poses_.back().data(), 7, pose_manifold_.get());
  }
  // The gauge.
  if (!poses_.empty()) {
    if (spec.gauge_prior) {
      problem_.AddResidualBlock(PosePriorFactor::Create(initial[0], SqrtInformation(config.gauge_sigma, config.gauge_sigma_deg * kDegToRad)),
                                nullptr, poses_[0].data());
    } else {
      problem_.SetParameterBlockConstant(poses_[0].data());
    }
  }
  // Tracking's motion between consecutive frames: weak, it holds what the planes leave free.
  const Eigen::Matrix<double, 6, 6> odometry = SqrtInformation(config.odometry_sigma, config.odometry_sigma_deg * kDegToRad);
  // Weak frames: tracking marked them degraded, or their observed planes' normals span fewer than
  // 3 directions (the smallest singular value of the normals stacked as rows below
  // min_normal_spread). Into a weak frame tracking's motion is what fixes the directions its
  // planes leave free, so it counts more.
  std::vector<bool> weak(frames.size(), false);
  for (size_t i = 0; i < frames.size(); ++i) {
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const PlaneObservation& o : frames[i]->planes) scatter += o.plane.normal * o.plane.normal.transpose();
    weak[i] = frames[i]->degraded || NormalSingularValues(scatter)[0] < config.min_normal_spread;
  }
  const Eigen::Matrix<double, 6, 6> degraded =
      SqrtInformation(config.degraded_odometry_sigma, config.degraded_odometry_sigma_deg * kDegToRad);
  for (size_t i = 1; i < frames.size(); ++i) {
    const Pose3 motion = frames[i - 1]->T_world_camera.inverse() * frames[i]->T_world_camera;
    problem_.AddResidualBlock(RelativePoseFactor::Create(motion, weak[i] ? degraded : odometry), nullptr, poses_[i - 1].data(),
                              poses_[i].data());
  }
  if (spec.tracking_sigma > 0.0) {
    const Eigen::Matrix<double, 6, 6> tracking = SqrtInformation(spec.tracking_sigma, spec.tracking_sigma_rad);
    for (size_t i = 0; i < frames.size(); ++i) {
      if (spec.tracking_prior_weak_only && !weak[i]) continue;
      problem_.AddResidualBlock(PosePriorFactor::Create(frames[i]->T_world_camera, tracking), nullptr, poses_[i].data());
    }
  }
  // One floor: the robot walks on one plane, so a horizontal landmark near the floor that frames
  // took for the floor is a duplicate of it (tracking placed it off by a pose error), and a frame
  // that sees such a duplicate but not the floor saw the floor.
  const int floor_id = map.Floor();
  if (floor_id >= 0 && config.floor_merge_distance > 0.0) {
    const Plane& f = map.landmarks[floor_id].plane;
    for (const PlaneLandmark& l : map.landmarks) {
      if (l.id == floor_id || l.floor_votes == 0) continue;
      if (l.plane.normal.dot(f.normal) < std::cos(config.floor_merge_angle_deg * kDegToRad)) continue;
      if (std::abs(l.plane.offset - f.offset) > config.floor_merge_distance) continue;
      floor_duplicates_.insert(l.id);
    }
  }
  if (spec.cuboids) AddCuboids(frames, initial);
  if (spec.estimate_noise && config.noise_initial_pixels > 0.0) pixel_correlation_ = 1.0 / config.noise_initial_pixels;

  // Plane observations: on a cuboid's face, or on a landmark.
  for (size_t i = 0; i < frames.size(); ++i) {
    const PlaneObservation* frame_floor = FloorSeenAsDuplicate(*frames[i], floor_id);
    for (const PlaneObservation& o : frames[i]->planes) {
      if (o.landmark < 0 || o.landmark >= static_cast<int>(map.landmarks.size())) {
        throw std::invalid_argument("frame " + std::to_string(frames[i]->frame) + " observes plane " + std::to_string(o.landmark) +
                                    ", the map has " + std::to_string(map.landmarks.size()));
      }
      const int landmark = &o == frame_floor ? floor_id : o.landmark;
      if (!face_of_landmark_.count(landmark)) {
        auto [it, added] = landmarks_.try_emplace(landmark, ToBlock(map.landmarks[landmark].plane));
        if (added) {
          problem_.AddParameterBlock(it->second.data(), 4, plane_manifold_.get());
          if (!spec.free_landmarks) problem_.SetParameterBlockConstant(it->second.data());
        }
      }
      observations_.push_back({nullptr, i, landmark, &o});
      AddPlaneBlock(&observations_.back());
    }
  }
  // Optional structure: landmarks the map's edges join at near right angles are perpendicular.
  if (spec.free_landmarks && config.structure_sigma_deg > 0.0) {
    for (const MapEdge& e : map.edges) {
      auto a = landmarks_.find(e.landmark_a), b = landmarks_.find(e.landmark_b);
      if (a == landmarks_.end() || b == landmarks_.end()) continue;
      const double angle = std::acos(std::clamp(std::abs(map.landmarks[e.landmark_a].plane.normal.dot(map.landmarks[e.landmark_b].plane.normal)), 0.0, 1.0));
      if (std::abs(angle - M_PI / 2) > config.structure_max_deviation_deg * kDegToRad) continue;
      problem_.AddResidualBlock(PerpendicularPlanesFactor::Create(config.structure_sigma_deg * kDegToRad), nullptr, a->second.data(),
                                b->second.data());
    }
  }
  // Cuboids on the floor.
  const int floor = map.Floor();
  const auto floor_block = landmarks_.find(floor);
  if (config.floor_contact && floor >= 0 && floor_block != landmarks_.end()) {
    const Plane& f = map.landmarks[floor].plane;
    for (Cuboid& c : cuboids_) {
      const Pose3 T = PoseFromBlock(c.pose.data());
      const Eigen::Vector3d z = T.linear().col(2);
      const Eigen::Vector3d bottom = T.translation() - 0.5 * c.dimensions[2] * z;
      if (z.dot(f.normal) < std::cos(config.face_max_angle_deg * kDegToRad) || std::abs(f.SignedDistance(bottom)) > config.contact_distance) continue;
      problem_.AddResidualBlock(BoxContactFactor::Create(config.contact_sigma, config.contact_sigma_deg * kDegToRad), nullptr,
                                c.pose.data(), c.dimensions.data(), floor_block->second.data());
      if (c.top_seen) c.held[2] = false;  // the top and the floor measure the height
    }
  }
  // Held dimensions: those nothing measures stay at their lower bound.
  for (Cuboid& c : cuboids_) {
    problem_.AddParameterBlock(c.dimensions.data(), 3);
    std::vector<int> held;
    for (int k = 0; k < 3; ++k) {
      if (c.held[k]) {
        held.push_back(k);
      } else {
        problem_.SetParameterLowerBound(c.dimensions.data(), k, config.min_dimension);
      }
    }
    if (held.size() == 3) {
      problem_.SetParameterBlockConstant(c.dimensions.data());
    } else if (!held.empty()) {
      dimension_manifolds_.push_back(std::make_unique<ceres::SubsetManifold>(3, held));
      problem_.SetManifold(c.dimensions.data(), dimension_manifolds_.back().get());
    }
  }
}

void FactorGraph::AddPlaneBlock(Observed* o) {
  if (o->block != nullptr) problem_.RemoveResidualBlock(o->block);
  const PlaneObservation& p = *o->observation;
  const double correlated = std::max(1.0, pixel_correlation_ * p.inliers);
  const Eigen::Matrix4d covariance = FlooredPlaneCovariance(p.plane, p.centroid, correlated * p.covariance, config_.plane_min_std_deg * kDegToRad,
                                                            config_.plane_min_std);
  o->normal_std = std::sqrt(std::max(0.0, covariance.topLeftCorner<3, 3>().trace() / 2.0));
  const Eigen::Vector4d at_centroid(p.centroid.x(), p.centroid.y(), p.centroid.z(), 1.0);
  o->offset_std = std::sqrt(std::max(0.0, at_centroid.dot(covariance * at_centroid)));
  const auto face = face_of_landmark_.find(o->landmark);
  if (face != face_of_landmark_.end()) {
    Cuboid& c = cuboids_[face->second.cuboid];
    o->block = problem_.AddResidualBlock(BoxFaceFactor::Create(face->second.axis, face->second.side, p.plane, covariance, 0.0), Loss(),
                                         poses_[o->pose].data(), c.pose.data(), c.dimensions.data());
  } else {
    o->block = problem_.AddResidualBlock(PlaneObservationFactor::Create(p.plane, covariance, 0.0), Loss(), poses_[o->pose].data(),
                                         landmarks_.at(o->landmark).data());
  }
}

void FactorGraph::AddCuboids(const std::vector<const FrameObservations*>& frames, const std::vector<Pose3>& initial) {
  std::vector<int> cuboid_of_object(map_.objects.size(), -1);
  const double face_cosine = std::cos(config_.face_max_angle_deg * kDegToRad);
  for (const MapObject& o : map_.objects) {
    if (o.structure) continue;  // a wall's piece, no object
    if (std::find(config_.cuboid_labels.begin(), config_.cuboid_labels.end(), o.label) == config_.cuboid_labels.end()) continue;
    Cuboid c;
    c.object = o.id;
    const Eigen::Matrix3d R = Orthonormal(o.axes);
    c.pose = ToBlock(MakePose(Eigen::Quaterniond(R), o.center));
    for (int k = 0; k < 3; ++k) c.dimensions[k] = std::max(o.dimensions[k], config_.min_dimension);
    std::vector<std::pair<int, Face>> faces;
    std::array<bool, 3> axes_seen{};
    for (int l : o.landmarks) {
      if (face_of_landmark_.count(l)) continue;  // a face of an earlier box
      double cosine = 0.0;
      const Eigen::Vector3d n = map_.landmarks[l].plane.normal;
      const int k = NearestAxis(R, n, &cosine);
      if (cosine < face_cosine) continue;  // not along an axis: stays a landmark
      faces.push_back({l, {static_cast<int>(cuboids_.size()), k, (R.col(k).dot(n) > 0.0) ? 1 : -1}});
      axes_seen[k] = true;
    }
    // Faces along two axes at least fix the box's orientation; else its faces stay landmarks.
    if (axes_seen[0] + axes_seen[1] + axes_seen[2] < 2) continue;
    for (const auto& [l, face] : faces) face_of_landmark_[l] = face;
    cuboid_of_object[o.id] = static_cast<int>(cuboids_.size());
    cuboids_.push_back(c);
    problem_.AddParameterBlock(cuboids_.back().pose.data(), 7, pose_manifold_.get());
    // The edges' common error: zero-mean with the systematic error's size, or none.
    double* bias = cuboids_.back().edge_bias.data();
    problem_.AddParameterBlock(bias, 3);
    if (config_.edge_bias_sigma > 0.0) {
      problem_.AddResidualBlock(new ceres::NormalPrior(Eigen::Matrix3d::Identity() / config_.edge_bias_sigma, Eigen::Vector3d::Zero()),
                                nullptr, bias);
    } else {
      problem_.SetParameterBlockConstant(bias);
    }
  }
  // Which faces the frames saw, per cuboid, axis and side.
  std::vector<std::array<std::array<bool, 2>, 3>> seen(cuboids_.size());
  for (const FrameObservations* f : frames) {
    for (const PlaneObservation& o : f->planes) {
      const auto face = face_of_landmark_.find(o.landmark);
      if (face != face_of_landmark_.end()) seen[face->second.cuboid][face->second.axis][face->second.side > 0] = true;
    }
  }
  // Each view's object: its centre, and its edges along the box's axes.
  std::vector<std::array<bool, 3>> measured(cuboids_.size(), {false, false, false});
  std::vector<Eigen::Vector3d> lower_bound(cuboids_.size(), Eigen::Vector3d::Zero());
  for (size_t i = 0; i < frames.size(); ++i) {
    for (const ObjectObservation& o : frames[i]->objects) {
      if (o.object < 0 || o.object >= static_cast<int>(map_.objects.size())) {
        throw std::invalid_argument("frame " + std::to_string(frames[i]->frame) + " observes object " + std::to_string(o.object) +
                                    ", the map has " + std::to_string(map_.objects.size()));
      }
      const int ci = cuboid_of_object[o.object];
      if (ci < 0 || frames[i]->frame < map_.objects[o.object].since_frame) continue;  // seen before it moved
      Cuboid& c = cuboids_[ci];
      const Eigen::Matrix3d R = PoseFromBlock(c.pose.data()).linear();
      problem_.AddResidualBlock(ObjectCenterFactor::Create(o.center, config_.center_sigma), Loss(), poses_[i].data(), c.pose.data());
      for (int j = 0; j < 3; ++j) {
        if (o.dimensions[j] <= 0.0) continue;
        double cosine = 0.0;
        const int k = NearestAxis(R, initial[i].linear() * o.axes.col(j), &cosine);
        if (o.dimension_complete[j]) measured[ci][k] = true;
        lower_bound[ci][k] = std::max(lower_bound[ci][k], o.dimensions[j]);
        problem_.AddResidualBlock(EdgeLengthWithBiasFactor::Create(k, o.dimensions[j], config_.edge_sigma, o.dimension_complete[j]),
                                  Loss(), c.dimensions.data(), c.edge_bias.data());
      }
    }
  }
  // A dimension is measured by a complete edge or by both its faces; else it is held at the
  // longest edge seen (the map's value when larger), a lower bound.
  for (size_t ci = 0; ci < cuboids_.size(); ++ci) {
    Cuboid& c = cuboids_[ci];
    c.top_seen = seen[ci][2][1];
    for (int k = 0; k < 3; ++k) {
      c.held[k] = !measured[ci][k] && !(seen[ci][k][0] && seen[ci][k][1]);
      if (c.held[k]) c.dimensions[k] = std::max(c.dimensions[k], lower_bound[ci][k]);
    }
  }
}

const PlaneObservation* FactorGraph::FloorSeenAsDuplicate(const FrameObservations& frame, int floor) const {
  const PlaneObservation* largest = nullptr;
  for (const PlaneObservation& o : frame.planes) {
    if (o.landmark == floor) return nullptr;  // it saw the floor itself: a duplicate is another patch
    if (floor_duplicates_.count(o.landmark) && (!largest || o.inliers > largest->inliers)) largest = &o;
  }
  return largest;
}

Plane FactorGraph::WorldPlane(int landmark) const {
  const auto face = face_of_landmark_.find(landmark);
  if (face == face_of_landmark_.end()) return PlaneFromBlock(landmarks_.at(landmark).data());
  const Cuboid& c = cuboids_[face->second.cuboid];
  const Pose3 T = PoseFromBlock(c.pose.data());
  const Eigen::Vector3d n = T.linear().col(face->second.axis) * face->second.side;
  return Plane{n, -n.dot(T.translation()) - 0.5 * c.dimensions[face->second.axis]};
}

void FactorGraph::Write(PlaneMap* map) const {
  for (const auto& [id, block] : landmarks_) {
    Plane p = PlaneFromBlock(block.data());
    if (p.normal.dot(map->landmarks[id].plane.normal) < 0.0) p = p.Flipped();
    map->landmarks[id].plane = p;
  }
  for (const auto& [id, face] : face_of_landmark_) map->landmarks[id].plane = WorldPlane(id);
  for (const Cuboid& c : cuboids_) {
    MapObject& o = map->objects[c.object];
    const Pose3 T = PoseFromBlock(c.pose.data());
    o.axes = T.linear();
    o.center = T.translation();
    for (int k = 0; k < 3; ++k) {
      o.dimensions[k] = c.dimensions[k];
      o.dimension_complete[k] = !c.held[k];
    }
    const auto grasp = face_of_landmark_.find(o.grasp_landmark);
    if (grasp != face_of_landmark_.end()) {
      o.grasp_axis = map->landmarks[o.grasp_landmark].plane.normal;
      o.has_grasp_axis = true;
    }
  }
}

bool FactorGraph::Covariances(PlaneMap* map, std::string* error, double* seconds) {
  const auto start = std::chrono::steady_clock::now();
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::SPARSE_QR;
  options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  options.num_threads = config_.threads;
  ceres::Covariance covariance(options);
  std::vector<std::pair<const double*, const double*>> blocks;
  for (const Cuboid& c : cuboids_) {
    blocks.emplace_back(c.pose.data(), c.pose.data());
    if (!problem_.IsParameterBlockConstant(c.dimensions.data())) blocks.emplace_back(c.dimensions.data(), c.dimensions.data());
  }
  if (blocks.empty()) {
    *seconds = 0.0;
    return true;
  }
  const bool ok = covariance.Compute(blocks, &problem_);
  *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!ok) {
    *error = "ceres::Covariance failed: the problem is rank deficient (an unobserved direction)";
    return false;
  }
  for (const Cuboid& c : cuboids_) {
    MapObject& o = map->objects[c.object];
    MapObject::Uncertainty& u = o.uncertainty;
    u = MapObject::Uncertainty();
    u.known = true;
    Eigen::Matrix<double, 6, 6, Eigen::RowMajor> pose;
    covariance.GetCovarianceBlockInTangentSpace(c.pose.data(), c.pose.data(), pose.data());
    const Eigen::Matrix3d rotation = pose.topLeftCorner<3, 3>();
    u.center_covariance = pose.bottomRightCorner<3, 3>();
    const Eigen::Matrix3d R = PoseFromBlock(c.pose.data()).linear();
    for (int k = 0; k < 3; ++k) u.axes_std_deg[k] = AxisStdDeg(rotation, R.col(k));
    if (!problem_.IsParameterBlockConstant(c.dimensions.data())) {
      Eigen::Matrix<double, 3, 3, Eigen::RowMajor> dims;
      covariance.GetCovarianceBlock(c.dimensions.data(), c.dimensions.data(), dims.data());
      u.dimension_covariance = dims;
    }
    for (int k = 0; k < 3; ++k) u.dimension_std[k] = c.held[k] ? -1.0 : std::sqrt(std::max(0.0, u.dimension_covariance(k, k)));
    const auto grasp = face_of_landmark_.find(o.grasp_landmark);
    if (grasp != face_of_landmark_.end()) u.grasp_axis_std_deg = AxisStdDeg(rotation, R.col(grasp->second.axis));
  }
  return true;
}

}  // namespace planemap::backend_detail
