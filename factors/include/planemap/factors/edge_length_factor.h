#pragma once
// Edge length: a real intersection along a box's axis k measures its dimension s_k.
//   complete edge (neither end cut): e = (s_k - l) / sigma;
//   cut edge (an end at the image border or next to missing depth): the box goes on beyond it,
//   so l only bounds s_k from below: e = max(0, l - s_k) / sigma, zero once s_k >= l.
// sigma is the length's standard deviation [m] (both ends' position error along the edge).
//
// EdgeLengthWithBiasFactor adds b_k, an error common to every view's edges along axis k (the
// frontend finds an end at a silhouette to about a pixel, the same way in every view, so that part
// does not average out): the measured length is s_k + b_k + noise, e = (s_k + b_k - l) / sigma as
// above with s_k + b_k for s_k. The back end holds b_k under a zero-mean prior of the systematic
// error's size, so the dimension's covariance keeps it.
#include <ceres/autodiff_cost_function.h>

namespace planemap {

class EdgeLengthFactor {
 public:
  EdgeLengthFactor(int axis, double length, double sigma, bool complete)
      : axis_(axis), length_(length), inverse_sigma_(1.0 / sigma), complete_(complete) {}

  // dimensions: [s_x s_y s_z] [m].
  template <typename T>
  bool operator()(const T* const dimensions, T* residual) const {
    const T shortfall = T(length_) - dimensions[axis_];
    residual[0] = (complete_ || shortfall > T(0.0) ? shortfall : T(0.0)) * T(inverse_sigma_);
    return true;
  }

  static ceres::CostFunction* Create(int axis, double length, double sigma, bool complete) {
    return new ceres::AutoDiffCostFunction<EdgeLengthFactor, 1, 3>(new EdgeLengthFactor(axis, length, sigma, complete));
  }

 private:
  const int axis_;
  const double length_;
  const double inverse_sigma_;
  const bool complete_;
};

class EdgeLengthWithBiasFactor {
 public:
  EdgeLengthWithBiasFactor(int axis, double length, double sigma, bool complete) : edge_(axis, length, sigma, complete), axis_(axis) {}

  // dimensions: [s_x s_y s_z], bias: [b_x b_y b_z] [m].
  template <typename T>
  bool operator()(const T* const dimensions, const T* const bias, T* residual) const {
    T measured[3] = {dimensions[0], dimensions[1], dimensions[2]};
    measured[axis_] += bias[axis_];
    return edge_(measured, residual);
  }

  static ceres::CostFunction* Create(int axis, double length, double sigma, bool complete) {
    return new ceres::AutoDiffCostFunction<EdgeLengthWithBiasFactor, 1, 3, 3>(new EdgeLengthWithBiasFactor(axis, length, sigma, complete));
  }

 private:
  const EdgeLengthFactor edge_;
  const int axis_;
};

}  // namespace planemap
