#pragma once
// Noise of a structured-light depth sensor (Kinect v1 / Xtion class), each part switchable.
#include <cstdint>
#include <string>

#include "planemap/core/config.h"
#include "planemap/core/image.h"
#include "planemap/core/intrinsics.h"

namespace planemap::sim {

struct SensorNoiseConfig {
  // Depth-dependent Gaussian noise, sigma(z) = sigma_coefficient * z^2
  // (Khoshelham & Elberink 2012 measured 1.425e-3 for the Kinect v1).
  bool gaussian = true;
  double sigma_coefficient = 1.425e-3;  // [1/m]
  // Disparity quantisation: the sensor measures disparity f*b/z in steps of `disparity_step`,
  // so depth comes in steps of z^2 * disparity_step / focal_baseline.
  bool quantization = true;
  double disparity_step = 0.125;  // [px] (1/8 sub-pixel, Kinect v1)
  double focal_baseline = 43.5;   // focal length x baseline of the IR pair [px m] (580 px x 7.5 cm)
  // Dropouts where the surface is seen at a grazing angle: none below start, all above full.
  bool grazing_dropout = true;
  double grazing_start_deg = 78.0;  // angle between ray and normal [deg]
  double grazing_full_deg = 88.0;   // [deg]
  // Dropouts next to depth discontinuities (projector shadow, mixed pixels).
  bool edge_dropout = true;
  double edge_min_jump = 0.04;            // neighbours differing more are a discontinuity [m]
  double edge_relative_jump = 0.02;       // ... or more than this fraction of the depth
  int edge_radius = 1;                    // pixels within this distance of one are affected [px]
  double edge_dropout_probability = 0.7;  // chance such a pixel has no reading
  // Scattered single-pixel dropouts.
  double random_dropout_probability = 0.002;
  // Working range; readings outside become 0 (no data).
  double min_depth = 0.4;  // [m]
  double max_depth = 8.0;  // [m]
  // Motion blur from camera motion during the exposure (off by default).
  bool motion_blur = false;
  double exposure = 0.02;           // exposure time before the frame stamp [s]
  int blur_samples = 5;             // poses rendered across the exposure
  double blur_max_spread = 0.03;    // depth spread across the exposure that voids a reading [m]

  std::string CrossCheck() const {
    if (min_depth >= max_depth) return "min_depth " + config_detail::ShortNumber(min_depth) + " must be below max_depth " + config_detail::ShortNumber(max_depth);
    if (grazing_start_deg > grazing_full_deg) return "grazing_start_deg must not exceed grazing_full_deg";
    return "";
  }

  template <class V>
  void VisitFields(V&& v) {
    v("gaussian", gaussian);
    v("sigma_coefficient", sigma_coefficient, Check::kNonNegative);
    v("quantization", quantization);
    v("disparity_step", disparity_step, Check::kPositive);
    v("focal_baseline", focal_baseline, Check::kPositive);
    v("grazing_dropout", grazing_dropout);
    v("grazing_start_deg", grazing_start_deg, Check::kNonNegative);
    v("grazing_full_deg", grazing_full_deg, Check::kNonNegative);
    v("edge_dropout", edge_dropout);
    v("edge_min_jump", edge_min_jump, Check::kPositive);
    v("edge_relative_jump", edge_relative_jump, Check::kNonNegative);
    v("edge_radius", edge_radius, Check::kNonNegative);
    v("edge_dropout_probability", edge_dropout_probability, Check::kProbability);
    v("random_dropout_probability", random_dropout_probability, Check::kProbability);
    v("min_depth", min_depth, Check::kNonNegative);
    v("max_depth", max_depth, Check::kPositive);
    v("motion_blur", motion_blur);
    v("exposure", exposure, Check::kNonNegative);
    v("blur_samples", blur_samples, Check::kPositive);
    v("blur_max_spread", blur_max_spread, Check::kPositive);
  }

  // Every part off: the exact depth passes through (range limits still apply).
  static SensorNoiseConfig None();

  // Standard deviation of the depth error the model produces at depth z on a surface that is
  // not dropped [m]: sqrt(sigma(z)^2 + step(z)^2 / 12) (quantisation as uniform rounding).
  double ExpectedDepthStd(double z) const;
  // Depth step of the disparity quantisation at depth z [m].
  double QuantizationStep(double z) const;
};

// What the ray caster knows per pixel that the noise model needs.
struct ExactDepth {
  DepthImage depth;          // [m], 0 where the ray hits nothing
  Image<float> incidence;    // angle between ray and surface normal [rad]
};

// Turns exact depth into a sensor reading. Deterministic for a given seed.
DepthImage ApplySensorNoise(const SensorNoiseConfig& config, const ExactDepth& exact,
                            std::uint64_t seed);

}  // namespace planemap::sim
