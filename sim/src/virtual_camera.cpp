#include "planemap/sim/virtual_camera.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace planemap::sim {
namespace {

constexpr double kNoHit = std::numeric_limits<double>::infinity();

// SplitMix64: decorrelates frame seeds derived from one base seed.
std::uint64_t Mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Pixel rectangle [u0, u1] x [v0, v1] (empty when u0 > u1) that can see a convex primitive with
// the given world corners and edges (pairs of corner indices). Clipped at a near plane first: the
// part in front of the camera is spanned by the corners in front and the points where edges cross
// the near plane, so a wall behind the camera costs nothing and one beside it only its pixels.
struct PixelBox {
  int u0, u1, v0, v1;
};

PixelBox ProjectBounds(const std::vector<Eigen::Vector3d>& corners_world, const std::vector<std::pair<int, int>>& edges,
                       const Pose3& T_camera_world, const CameraIntrinsics& camera) {
  // Any hit nearer than this is far below the sensor's range; projections stay finite.
  constexpr double kNear = 1e-9;
  std::vector<Eigen::Vector3d> corners;
  for (const Eigen::Vector3d& p_w : corners_world) corners.push_back(T_camera_world * p_w);
  double umin = kNoHit, vmin = kNoHit, umax = -kNoHit, vmax = -kNoHit;
  auto extend = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector2d uv = camera.Project(p);
    umin = std::min(umin, uv.x()); umax = std::max(umax, uv.x());
    vmin = std::min(vmin, uv.y()); vmax = std::max(vmax, uv.y());
  };
  for (const Eigen::Vector3d& p : corners) {
    if (p.z() >= kNear) extend(p);
  }
  for (const auto& [i, j] : edges) {
    const Eigen::Vector3d &a = corners[i], &b = corners[j];
    if ((a.z() < kNear) == (b.z() < kNear)) continue;
    const double s = (kNear - a.z()) / (b.z() - a.z());
    Eigen::Vector3d p = a + s * (b - a);
    p.z() = kNear;
    extend(p);
  }
  if (umin > umax) return {0, -1, 0, -1};  // wholly behind the camera
  // One pixel of margin: the ray test itself decides, the box only skips pixels. Clamped in
  // floating point first: near the near plane the projections are huge.
  auto clamp = [](double x, int lo, int hi) {
    return static_cast<int>(std::clamp(x, static_cast<double>(lo), static_cast<double>(hi)));
  };
  return {clamp(std::floor(umin) - 1, 0, camera.width - 1), clamp(std::ceil(umax) + 1, 0, camera.width - 1),
          clamp(std::floor(vmin) - 1, 0, camera.height - 1), clamp(std::ceil(vmax) + 1, 0, camera.height - 1)};
}

// Corner i of a cuboid has coordinate sign bit k along its axis k; an edge joins two corners one
// bit apart.
std::vector<Eigen::Vector3d> CuboidCorners(const Cuboid& c) {
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d s((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5);
    corners.push_back(c.T_world_box * s.cwiseProduct(c.dimensions));
  }
  return corners;
}

const std::vector<std::pair<int, int>>& CuboidEdges() {
  static const std::vector<std::pair<int, int>> edges = [] {
    std::vector<std::pair<int, int>> e;
    for (int i = 0; i < 8; ++i) {
      for (int bit : {1, 2, 4}) {
        if (!(i & bit)) e.emplace_back(i, i | bit);
      }
    }
    return e;
  }();
  return edges;
}

// Corners of a rectangle in the order (-u -v), (-u +v), (+u -v), (+u +v), and its four edges.
std::vector<Eigen::Vector3d> SurfaceCorners(const Surface& s) {
  std::vector<Eigen::Vector3d> corners;
  for (double a : {-1.0, 1.0}) {
    for (double b : {-1.0, 1.0}) corners.push_back(s.center_world + a * s.half_u * s.axis_u + b * s.half_v * s.axis_v);
  }
  return corners;
}

const std::vector<std::pair<int, int>> kRectangleEdges = {{0, 1}, {2, 3}, {0, 2}, {1, 3}};

// Slab test of a ray against a cuboid. Returns the ray parameter of the entry point and the face
// it enters through (kFaceNames order), or kNoHit. Rays starting inside the box see nothing of it.
double IntersectCuboid(const Cuboid& c, const Eigen::Vector3d& origin_box, const Eigen::Vector3d& dir_box, int* face) {
  double t_near = -kNoHit, t_far = kNoHit;
  int near_face = -1;
  for (int a = 0; a < 3; ++a) {
    const double h = c.dimensions[a] / 2;
    if (std::abs(dir_box[a]) < 1e-15) {
      if (std::abs(origin_box[a]) > h) return kNoHit;
      continue;
    }
    double t0 = (-h - origin_box[a]) / dir_box[a];
    double t1 = (h - origin_box[a]) / dir_box[a];
    // Entering through the -a face when moving along +a, else through the +a face.
    int entry_face = dir_box[a] > 0 ? 2 * a + 1 : 2 * a;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_near) { t_near = t0; near_face = entry_face; }
    t_far = std::min(t_far, t1);
  }
  if (t_near > t_far || t_near <= 0.0) return kNoHit;
  *face = near_face;
  return t_near;
}

}  // namespace

struct VirtualCamera::RayCast {
  ExactDepth exact;
  LabelImage labels;
};

VirtualCamera::VirtualCamera(Scene scene, const CameraIntrinsics& camera, const RenderConfig& config)
    : scene_(std::move(scene)), camera_(camera), config_(config) {
  ValidateConfig(camera_, "camera.");
  ValidateConfig(config_, "render.");
  if (config_.light_direction.size() != 3 || Eigen::Vector3d(config_.light_direction.data()).norm() == 0) {
    throw std::invalid_argument("render.light_direction needs 3 numbers, not all zero");
  }
  light_world_ = Eigen::Vector3d(config_.light_direction.data()).normalized();
  // Flat face colour (or a marker module's grey) under ambient plus Lambertian light, so faces of
  // one box differ in brightness as in a real image: per surface label, once.
  const size_t labels = scene_.surfaces.size() + 1;
  markers_on_.assign(labels, {});
  for (size_t i = 0; i < scene_.markers.size(); ++i) {
    const std::uint16_t surface = scene_.markers[i].surface;
    if (surface >= 1 && surface < labels) markers_on_[surface].push_back(i);
  }
  shaded_.assign(labels, Rgb8{0, 0, 0});
  light_.assign(labels, 0.0);
  for (const Surface& s : scene_.surfaces) {
    light_[s.label] = config_.ambient + (1.0 - config_.ambient) * std::abs(s.plane_world.normal.dot(light_world_));
    for (int k = 0; k < 3; ++k) shaded_[s.label][k] = static_cast<std::uint8_t>(std::lround(s.color[k] * light_[s.label]));
  }
}

std::uint64_t VirtualCamera::FrameSeed(int index) const {
  return Mix(Mix(static_cast<std::uint64_t>(config_.seed)) ^ static_cast<std::uint64_t>(index));
}

VirtualCamera::RayCast VirtualCamera::Cast(const Pose3& T_world_camera) const {
  const int w = camera_.width, h = camera_.height;
  const Pose3 T_camera_world = T_world_camera.inverse();
  const Eigen::Matrix3d R_wc = T_world_camera.linear();
  const Eigen::Vector3d origin = T_world_camera.translation();

  // Nearest hit per pixel: ray parameter along the z = 1 ray (so it is the depth) and the label.
  std::vector<double> best(static_cast<size_t>(w) * h, kNoHit);
  LabelImage labels(w, h, 0);

  // Floor and walls: rectangles. Each pixel's ray in the world, computed once for all of them.
  std::vector<Eigen::Vector3d> dirs(static_cast<size_t>(w) * h);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) dirs[static_cast<size_t>(v) * w + u] = R_wc * camera_.Ray(u, v);
  }
  for (size_t index : scene_.flat_surfaces) {
    const Surface& s = scene_.surfaces[index];
    const PixelBox box = ProjectBounds(SurfaceCorners(s), kRectangleEdges, T_camera_world, camera_);
#pragma omp parallel for schedule(static)
    for (int v = box.v0; v <= box.v1; ++v) {
      for (int u = box.u0; u <= box.u1; ++u) {
        const size_t i = static_cast<size_t>(v) * w + u;
        const Eigen::Vector3d& dir = dirs[i];
        const std::optional<double> t = s.plane_world.IntersectRay(origin, dir);
        if (!t || *t <= 0.0) continue;
        const Eigen::Vector3d local = origin + *t * dir - s.center_world;
        if (std::abs(local.dot(s.axis_u)) > s.half_u || std::abs(local.dot(s.axis_v)) > s.half_v) continue;
        if (*t < best[i]) { best[i] = *t; labels.at(u, v) = s.label; }
      }
    }
  }
  // Boxes: slab test in each box's frame.
  for (const Cuboid& c : scene_.cuboids) {
    const PixelBox box = ProjectBounds(CuboidCorners(c), CuboidEdges(), T_camera_world, camera_);
    const Pose3 T_box_world = c.T_world_box.inverse();
    const Eigen::Vector3d origin_box = T_box_world * origin;
    const Eigen::Matrix3d R_box_camera = T_box_world.linear() * R_wc;
#pragma omp parallel for schedule(static)
    for (int v = box.v0; v <= box.v1; ++v) {
      for (int u = box.u0; u <= box.u1; ++u) {
        int face = -1;
        const double t = IntersectCuboid(c, origin_box, R_box_camera * camera_.Ray(u, v), &face);
        const size_t i = static_cast<size_t>(v) * w + u;
        if (t < best[i]) { best[i] = t; labels.at(u, v) = c.face_labels[face]; }
      }
    }
  }

  // Each surface's normal in the camera, once per frame.
  std::vector<Eigen::Vector3d> normals_camera(scene_.surfaces.size() + 1, Eigen::Vector3d::Zero());
  for (const Surface& s : scene_.surfaces) normals_camera[s.label] = R_wc.transpose() * s.plane_world.normal;
  RayCast cast{{DepthImage(w, h, 0.0f), Image<float>(w, h, 0.0f)}, std::move(labels)};
#pragma omp parallel for schedule(static)
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const size_t i = static_cast<size_t>(v) * w + u;
      if (best[i] == kNoHit) continue;
      const Eigen::Vector3d ray = camera_.Ray(u, v);
      const Eigen::Vector3d& n_c = normals_camera.at(cast.labels.at(u, v));
      cast.exact.depth.at(u, v) = static_cast<float>(best[i]);
      cast.exact.incidence.at(u, v) = static_cast<float>(std::acos(std::min(1.0, std::abs(n_c.dot(ray)) / ray.norm())));
    }
  }
  return cast;
}

ColorImage VirtualCamera::ShadeColor(const RayCast& cast, const Pose3& T_world_camera) const {
  // Each surface's shaded colour comes from the constructor; only pixels of a surface with
  // markers need their point, to see whether a marker's module covers it (the last marker listed
  // that covers it wins).
  ColorImage color(camera_.width, camera_.height, Rgb8{0, 0, 0});
#pragma omp parallel for schedule(static)
  for (int v = 0; v < camera_.height; ++v) {
    for (int u = 0; u < camera_.width; ++u) {
      const std::uint16_t label = cast.labels.at(u, v);
      if (label == 0) continue;
      color.at(u, v) = shaded_[label];
      if (markers_on_[label].empty()) continue;
      const Eigen::Vector3d p_world = T_world_camera * (cast.exact.depth.at(u, v) * camera_.Ray(u, v));
      const std::uint8_t* module = nullptr;
      for (size_t index : markers_on_[label]) {
        const Marker& m = scene_.markers[index];
        const Eigen::Vector3d local = p_world - m.center_world;
        const double x = local.dot(m.axis_u) / m.size + 0.5, y = local.dot(m.axis_v) / m.size + 0.5;
        if (x < 0.0 || x >= 1.0 || y < 0.0 || y >= 1.0) continue;
        module = &m.bits.at(static_cast<int>(x * m.bits.width()), static_cast<int>(y * m.bits.height()));
      }
      if (!module) continue;
      const std::uint8_t grey = static_cast<std::uint8_t>(std::lround(*module * light_[label]));
      color.at(u, v) = Rgb8{grey, grey, grey};
    }
  }
  return color;
}

RenderedFrame VirtualCamera::RenderExact(const Pose3& T_world_camera) const {
  RayCast cast = Cast(T_world_camera);
  RenderedFrame frame;
  frame.color = ShadeColor(cast, T_world_camera);
  frame.depth = std::move(cast.exact.depth);
  frame.labels = std::move(cast.labels);
  return frame;
}

RenderedFrame VirtualCamera::Render(const Pose3& T_world_camera, std::uint64_t seed,
                                    const std::optional<Pose3>& T_world_camera_exposure_start) const {
  if (!config_.add_noise) return RenderExact(T_world_camera);
  const SensorNoiseConfig& noise = config_.noise;
  RayCast cast = Cast(T_world_camera);
  RenderedFrame frame;
  frame.color = ShadeColor(cast, T_world_camera);
  frame.depth = ApplySensorNoise(noise, cast.exact, seed);
  frame.labels = std::move(cast.labels);
  if (!noise.motion_blur || !T_world_camera_exposure_start || noise.blur_samples < 2) return frame;

  // Motion blur: average the colour over the exposure; a structured-light sensor cannot decode a
  // pattern smeared across a depth change, so readings whose exact depth spreads too much vanish.
  const int n = noise.blur_samples;
  const size_t pixels = frame.depth.size();
  std::vector<Eigen::Vector3d> color_sum(pixels, Eigen::Vector3d::Zero());
  std::vector<float> zmin(pixels, std::numeric_limits<float>::infinity()), zmax(pixels, 0.0f);
  for (int k = 0; k < n; ++k) {
    const Pose3 T_k = Interpolate(*T_world_camera_exposure_start, T_world_camera, static_cast<double>(k) / (n - 1));
    const RenderedFrame sub = RenderExact(T_k);
    for (size_t i = 0; i < pixels; ++i) {
      const Rgb8& c = sub.color.pixels()[i];
      color_sum[i] += Eigen::Vector3d(c[0], c[1], c[2]);
      const float z = sub.depth.pixels()[i];
      zmin[i] = std::min(zmin[i], IsValidDepth(z) ? z : 0.0f);
      zmax[i] = std::max(zmax[i], z);
    }
  }
  for (size_t i = 0; i < pixels; ++i) {
    for (int k = 0; k < 3; ++k) frame.color.pixels()[i][k] = static_cast<std::uint8_t>(std::lround(color_sum[i][k] / n));
    if (zmax[i] - zmin[i] > noise.blur_max_spread) frame.depth.pixels()[i] = 0.0f;
  }
  return frame;
}

}  // namespace planemap::sim
