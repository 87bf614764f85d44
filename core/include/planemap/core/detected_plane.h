#pragma once
// A plane found in one frame, in that frame's camera optical frame.
#include <vector>

#include <Eigen/Core>

#include "planemap/core/plane.h"
#include "planemap/core/pose.h"

namespace planemap {

struct DetectedPlane {
  int id = 0;                     // index in its frame's plane list
  Plane plane;                    // camera frame; normal toward the camera (offset d > 0)
  std::vector<int> inliers;       // pixel indices v * width + u
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // mean of the inliers [m]
  // Covariance of (n, d) from the inliers' least-squares fit, in the 3-dimensional tangent space
  // of the constraint |n| = 1 (so it has rank 3 and n^T C n = 0 for its normal part).
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
  double rms = 0.0;               // weighted RMS point-to-plane distance of the inliers [m]
  // Axis-aligned box of the inlier points [m], kept by the segmenters that make the plane (they
  // read every inlier anyway); empty when not computed, and then readers compute it.
  Box3 bounds;
  // Found among the pixels no cell of the organized segmenter fitted (a face seen as a thin
  // strip): a frame's objects use it; tracking leaves it out (its normal rests on a strip's
  // width), and the objects it is a face of.
  bool strip = false;
};

// Least-squares plane through points given by their first and second moments: the normal is the
// eigenvector of the smallest eigenvalue of the scatter matrix. Returns a plane oriented toward
// the origin (d > 0), its RMS residual, and the covariance of (n, d) as in DetectedPlane.
struct PlaneFit {
  Plane plane;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double rms = 0.0;
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
  bool ok = false;  // false for fewer than 3 points or collinear points
};

// Running, optionally weighted sums of points for plane fits; merging two is adding their sums.
// With weights w_i proportional to 1 / sigma_i^2 (sigma_i a point's noise), the fit is the
// maximum-likelihood plane and its covariance accounts for noise that differs between points.
struct PointMoments {
  double n = 0.0;                                       // number of points
  double w = 0.0;                                       // sum of weights
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();        // sum of w p
  Eigen::Matrix3d sum_outer = Eigen::Matrix3d::Zero();  // sum of w p p^T

  void Add(const Eigen::Vector3d& p, double weight = 1.0) {
    n += 1.0;
    w += weight;
    sum += weight * p;
    sum_outer += weight * p * p.transpose();
  }
  PointMoments& operator+=(const PointMoments& o) {
    n += o.n;
    w += o.w;
    sum += o.sum;
    sum_outer += o.sum_outer;
    return *this;
  }
  Eigen::Vector3d Mean() const { return sum / w; }
  // Weighted scatter about the mean, divided by the sum of weights.
  Eigen::Matrix3d Covariance() const { return sum_outer / w - Mean() * Mean().transpose(); }
};

// The moments of the same points moved by T (p -> T p): exact, as the sums are polynomial in p.
inline PointMoments TransformMoments(const Pose3& T, const PointMoments& m) {
  const Eigen::Matrix3d R = T.linear();
  const Eigen::Vector3d t = T.translation();
  PointMoments out = m;
  out.sum = R * m.sum + m.w * t;
  const Eigen::Matrix3d cross = R * m.sum * t.transpose();
  out.sum_outer = R * m.sum_outer * R.transpose() + cross + cross.transpose() + m.w * t * t.transpose();
  return out;
}

// Weight of a depth-camera point at depth z for plane fits: 1 / z^4, as a structured-light
// sensor's depth noise grows with z^2.
inline double DepthNoiseWeight(double z) { return 1.0 / (z * z * z * z); }

PlaneFit FitPlane(const PointMoments& moments);

}  // namespace planemap
