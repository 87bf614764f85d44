#include "planemap/sim/sensor_noise.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <opencv2/imgproc.hpp>

namespace planemap::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Pixels next to a depth discontinuity of the exact depth (or next to a pixel without surface).
std::vector<bool> DiscontinuityMask(const SensorNoiseConfig& config, const DepthImage& z) {
  const int w = z.width(), h = z.height();
  std::vector<bool> edge(z.size(), false);
  auto jump = [&](float a, float b) {
    if (!IsValidDepth(a) || !IsValidDepth(b)) return IsValidDepth(a) != IsValidDepth(b);
    return std::abs(a - b) > std::max(config.edge_min_jump, config.edge_relative_jump * std::min(a, b));
  };
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const float a = z.at(u, v);
      if ((u + 1 < w && jump(a, z.at(u + 1, v))) || (v + 1 < h && jump(a, z.at(u, v + 1)))) {
        edge[static_cast<size_t>(v) * w + u] = true;
        if (u + 1 < w && jump(a, z.at(u + 1, v))) edge[static_cast<size_t>(v) * w + u + 1] = true;
        if (v + 1 < h && jump(a, z.at(u, v + 1))) edge[static_cast<size_t>(v + 1) * w + u] = true;
      }
    }
  }
  // Grow by the radius (square neighbourhood, clipped at the border): OpenCV's dilation. A radius
  // past the image's size grows no further (and no longer runs for hours).
  const int r = std::min(config.edge_radius, std::max(w, h));
  if (r <= 0) return edge;
  cv::Mat mask(h, w, CV_8U);
  for (size_t i = 0; i < edge.size(); ++i) mask.data[i] = edge[i] ? 1 : 0;
  cv::dilate(mask, mask, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * r + 1, 2 * r + 1)));
  std::vector<bool> grown(edge.size());
  for (size_t i = 0; i < grown.size(); ++i) grown[i] = mask.data[i] != 0;
  return grown;
}

}  // namespace

SensorNoiseConfig SensorNoiseConfig::None() {
  SensorNoiseConfig c;
  c.gaussian = c.quantization = c.grazing_dropout = c.edge_dropout = c.motion_blur = false;
  c.random_dropout_probability = 0.0;
  return c;
}

double SensorNoiseConfig::QuantizationStep(double z) const {
  return z * z * disparity_step / focal_baseline;
}

double SensorNoiseConfig::ExpectedDepthStd(double z) const {
  const double sigma = gaussian ? sigma_coefficient * z * z : 0.0;
  const double step = quantization ? QuantizationStep(z) : 0.0;
  return std::sqrt(sigma * sigma + step * step / 12.0);
}

DepthImage ApplySensorNoise(const SensorNoiseConfig& config, const ExactDepth& exact, std::uint64_t seed) {
  const DepthImage& z_exact = exact.depth;
  DepthImage depth(z_exact.width(), z_exact.height(), 0.0f);
  const std::vector<bool> near_edge = config.edge_dropout ? DiscontinuityMask(config, z_exact) : std::vector<bool>();
  const double graze0 = config.grazing_start_deg * kDegToRad, graze1 = config.grazing_full_deg * kDegToRad;
  const int w = z_exact.width();

  // One generator per row, seeded from the frame seed and the row: deterministic whatever the
  // number of threads.
#pragma omp parallel for schedule(static)
  for (int v = 0; v < z_exact.height(); ++v) {
    std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(v) * 0xBF58476D1CE4E5B9ull + 1);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (int u = 0; u < w; ++u) {
      const size_t i = static_cast<size_t>(v) * w + u;
      const double z = z_exact.pixels()[i];
      if (!IsValidDepth(static_cast<float>(z))) continue;
      // Every pixel draws the same random numbers whatever is switched on, so turning one part
      // of the model on or off leaves the others' draws unchanged.
      const double u_graze = uniform(rng), u_edge = uniform(rng), u_random = uniform(rng), g = normal(rng);
      if (config.grazing_dropout) {
        const double angle = exact.incidence.pixels()[i];
        const double p = graze1 > graze0 ? (angle - graze0) / (graze1 - graze0) : (angle >= graze0 ? 1.0 : 0.0);
        if (u_graze < p) continue;
      }
      if (config.edge_dropout && near_edge[i] && u_edge < config.edge_dropout_probability) continue;
      if (u_random < config.random_dropout_probability) continue;
      double measured = z;
      if (config.gaussian) measured += config.sigma_coefficient * z * z * g;
      if (config.quantization && measured > 0.0) {
        // Depth z is disparity f*b/z; the sensor reports disparity in steps of disparity_step.
        const double disparity = config.focal_baseline / measured;
        const double quantized = std::round(disparity / config.disparity_step) * config.disparity_step;
        measured = quantized > 0.0 ? config.focal_baseline / quantized : 0.0;
      }
      if (measured < config.min_depth || measured > config.max_depth) continue;
      depth.pixels()[i] = static_cast<float>(measured);
    }
  }
  return depth;
}

}  // namespace planemap::sim
