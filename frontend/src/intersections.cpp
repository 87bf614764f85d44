#include "planemap/frontend/intersections.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <Eigen/Dense>

#include "planemap/core/statistics.h"
#include "planemap/frontend/plane_segmenter.h"

#include "assign_pixels.h"  // GrowsWithDepth

namespace planemap {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

Eigen::Vector3d PointAt(const Cloud& cloud, int i) { return {cloud[i].x, cloud[i].y, cloud[i].z}; }

// A pixel window: only inliers inside it can lie near the other plane (a speed-up, nothing more).
struct Window {
  int u0 = 0, u1 = 0, v0 = 0, v1 = 0;
};

// Calls fn(point) for each of `pixels` (sorted by pixel index) inside `window`.
template <typename Fn>
void ForPixelsIn(const std::vector<int>& pixels, const Window& window, const Cloud& cloud, Fn&& fn) {
  const int w = static_cast<int>(cloud.width);
  // Raw pointers in locals: fn appends to vectors, which as far as the compiler knows might
  // hold the inliers' or the cloud's bounds, and would have them read again for every point.
  const int* it = pixels.data();
  const int* const last = it + pixels.size();
  const pcl::PointXYZRGB* const points = cloud.points.data();
  for (int v = window.v0; v <= window.v1 && it != last; ++v) {
    it = std::lower_bound(it, last, v * w + window.u0);
    for (const int end = v * w + window.u1; it != last && *it <= end; ++it) {
      // The walk waits on each point's first read (perf: about half of this function's time),
      // and a row's run is too short for the processor to start fetching ahead by itself.
      if (last - it > 16) __builtin_prefetch(&points[it[16]]);
      const pcl::PointXYZRGB& p = points[*it];
      fn(Eigen::Vector3d(p.x, p.y, p.z));
    }
  }
}

}  // namespace

Eigen::Vector3d AlongRayOntoPlane(const Plane& plane, const Eigen::Vector3d& p) {
  // Plane::IntersectRay from the origin along p, written out: t = -d / (n . p), none if t <= 0 or
  // if the ray runs along the plane, |n . p| < 1e-12 max(1, |p|). As |p| <= |p|_1, a ray with
  // |n . p| of at least twice that bound taken in |p|_1 does not: almost every call is decided
  // without the square root of |p|, and the same way. (The same arithmetic as IntersectRay: this
  // runs for tens of thousands of band points a frame.)
  const double denom = plane.normal.dot(p);
  if (!(std::abs(denom) >= 2e-12 * std::max(1.0, p.cwiseAbs().sum())) &&
      std::abs(denom) < 1e-12 * std::max(1.0, p.norm())) {
    return p;
  }
  const double t = -plane.offset / denom;
  return t > 0.0 ? Eigen::Vector3d(t * p) : p;
}

namespace {

// Whether some point of `box` lies less than `half_width` from `plane`: the range of the plane's
// signed distance over the box is taken at its corners.
bool BoxMeetsSlab(const Box3& box, const Plane& plane, double half_width) {
  if (box.Empty()) return false;
  double low = plane.offset, high = plane.offset;
  for (int k = 0; k < 3; ++k) {
    const double at_low = plane.normal[k] * box.low[k], at_high = plane.normal[k] * box.high[k];
    low += std::min(at_low, at_high);
    high += std::max(at_low, at_high);
  }
  return low < half_width && high > -half_width;
}

// Eqs. (2)-(5): pixels of `own` (its inliers, then its fringe) within d_thresh of both planes and
// farther than d_min from both; and (band) its pixels from d_thresh to band_width away from `other`. With band_on_plane,
// a band point moves along its ray onto `own` when its distance to `own` is within the depth
// noise (band_on_plane_max_sigma robust standard deviations of the band's distances) and no
// other of `planes` is nearer: a point beyond either may be a neighbouring surface's pixel the
// segmenter gave to `own` (a side face's pixel beside a corner), which its ray would carry past
// the corner; it stays where it was.
// `distance` and `sorted` are scratch space, reused from call to call.
void CollectEdgePoints(const DetectedPlane& own, const std::vector<int>& own_fringe, const DetectedPlane& other,
                       const std::vector<const DetectedPlane*>& nearby,
                       const Window& window, const Cloud& cloud, const IntersectionConfig& c,
                       std::vector<Eigen::Vector3d>* points, std::vector<Eigen::Vector3d>* band,
                       std::vector<double>* distance_scratch, std::vector<double>* sorted) {
  std::vector<double>& distance = *distance_scratch;  // of each band point to `own` [m]; negative: nearer another plane
  distance.clear();
  const size_t first = band->size();
  // Copies the loop can keep in registers (the vectors it appends to might alias the originals).
  const Plane own_plane = own.plane, other_plane = other.plane;
  const double d_thresh = c.d_thresh, d_min = c.d_min, band_width = c.band_width;
  const bool band_on_plane = c.band_on_plane;
  const double far = std::max(d_thresh, band_width);
  auto visit = [&](const Eigen::Vector3d& p) {
    const double d_other = std::abs(other_plane.SignedDistance(p));  // eq. (3) / (5)
    if (d_other >= far) return;                                      // most of the window: far from the edge
    const double d_own = std::abs(own_plane.SignedDistance(p));      // eq. (2) / (4)
    if (d_own < d_thresh && d_other < d_thresh && d_own >= d_min && d_other >= d_min) points->push_back(p);
    if (d_other < d_thresh || d_other >= band_width) return;
    bool own_nearest = true;
    for (size_t k = 0; band_on_plane && own_nearest && k < nearby.size(); ++k) {
      own_nearest = nearby[k] == &own || std::abs(nearby[k]->plane.SignedDistance(p)) >= d_own;
    }
    band->push_back(p);
    distance.push_back(own_nearest ? d_own : -1.0);
  };
  ForPixelsIn(own.inliers, window, cloud, visit);
  ForPixelsIn(own_fringe, window, cloud, visit);
  if (!c.band_on_plane || distance.empty()) return;
  sorted->assign(distance.begin(), distance.end());
  const auto middle = sorted->begin() + static_cast<std::ptrdiff_t>(sorted->size() / 2);
  std::nth_element(sorted->begin(), middle, sorted->end());
  const double sigma = 1.4826 * std::max(0.0, *middle);  // median absolute distance
  for (size_t k = 0; k < distance.size(); ++k) {
    if (distance[k] >= 0.0 && distance[k] <= c.band_on_plane_max_sigma * sigma) {
      (*band)[first + k] = AlongRayOntoPlane(own.plane, (*band)[first + k]);
    }
  }
}

// Whether most of `band` (one plane's points beside the edge) within [low, high] along the line
// lies behind `other` (normals face the camera): true on a solid's own edge.
bool MostlyBehind(const std::vector<Eigen::Vector3d>& band, const Plane& other, const Eigen::Vector3d& origin,
                  const Eigen::Vector3d& direction, double low, double high) {
  int behind = 0, total = 0;
  for (const Eigen::Vector3d& p : band) {
    const double t = direction.dot(p - origin);
    if (t < low || t > high) continue;
    ++total;
    behind += other.SignedDistance(p) < 0.0;
  }
  return 2 * behind > total;
}

// The band points' extent along the line is the plane's own extent there, untouched by pixels
// the noise moved between the two planes near the line.

struct Interval {
  double low = 0.0, high = 0.0;  // along the line [m]
  Eigen::Vector3d low_point, high_point;  // the extreme edge points
  int points = 0;
};

// Eqs. (2)-(5) hold all along the line where one plane runs on past the other (the floor past a
// box's face), so the real intersection is where both planes have edge points: the longest
// stretch of the line, without gaps over max_gap, that both cover.
std::optional<Interval> SharedSpan(const std::vector<Eigen::Vector3d>& points_a,
                                   const std::vector<Eigen::Vector3d>& points_b, const Eigen::Vector3d& origin,
                                   const Eigen::Vector3d& direction, const IntersectionConfig& c) {
  if (points_a.empty() || points_b.empty()) return std::nullopt;
  const double bin = c.max_gap / 2.0;
  double t_min = 1e30, t_max = -1e30;
  for (const auto* set : {&points_a, &points_b}) {
    for (const Eigen::Vector3d& p : *set) {
      const double t = direction.dot(p - origin);
      t_min = std::min(t_min, t);
      t_max = std::max(t_max, t);
    }
  }
  const int bins = static_cast<int>((t_max - t_min) / bin) + 1;
  std::vector<int> count_a(bins, 0), count_b(bins, 0);
  auto bin_of = [&](const Eigen::Vector3d& p) { return static_cast<int>((direction.dot(p - origin) - t_min) / bin); };
  for (const Eigen::Vector3d& p : points_a) ++count_a[bin_of(p)];
  for (const Eigen::Vector3d& p : points_b) ++count_b[bin_of(p)];
  // Runs of bins both planes cover, bridging single empty bins (gaps up to max_gap).
  int best_first = -1, best_last = -1, best_count = 0;
  for (int i = 0; i < bins;) {
    if (count_a[i] == 0 || count_b[i] == 0) {
      ++i;
      continue;
    }
    int last = i, count = 0, j = i;
    while (j < bins) {
      if (count_a[j] > 0 && count_b[j] > 0) {
        last = j;
        count += count_a[j] + count_b[j];
        ++j;
      } else if (j + 1 < bins && count_a[j + 1] > 0 && count_b[j + 1] > 0) {
        ++j;  // bridge one empty bin
      } else {
        break;
      }
    }
    if (count > best_count) {
      best_count = count;
      best_first = i;
      best_last = last;
    }
    i = last + 1;
  }
  if (best_first < 0) return std::nullopt;
  // Within the run, the edge spans where both planes' points are: the overlap of their extents,
  // each taken without its few most extreme points (strays the noise put beyond the end).
  const double run_low = t_min + best_first * bin, run_high = t_min + (best_last + 1) * bin;
  auto extent = [&](const std::vector<Eigen::Vector3d>& set, double* low, double* high) {
    std::vector<double> t;
    for (const Eigen::Vector3d& p : set) {
      const double x = direction.dot(p - origin);
      if (x >= run_low && x <= run_high) t.push_back(x);
    }
    if (t.empty()) return false;
    const size_t trim = std::min(t.size() / 2, static_cast<size_t>(c.end_trim_fraction * t.size()));
    if (trim == 0) {  // the default: the extremes themselves, in one pass
      const auto [lowest, highest] = std::minmax_element(t.begin(), t.end());
      *low = *lowest;
      *high = *highest;
      return true;
    }
    std::nth_element(t.begin(), t.begin() + trim, t.end());
    *low = t[trim];
    std::nth_element(t.begin(), t.end() - 1 - trim, t.end());
    *high = t[t.size() - 1 - trim];
    return true;
  };
  double a_low, a_high, b_low, b_high;
  if (!extent(points_a, &a_low, &a_high) || !extent(points_b, &b_low, &b_high)) return std::nullopt;
  Interval span;
  span.low = std::max(a_low, b_low);
  span.high = std::min(a_high, b_high);
  if (span.high <= span.low) return std::nullopt;
  double lowest = 1e30, highest = -1e30;
  for (const auto* set : {&points_a, &points_b}) {
    for (const Eigen::Vector3d& p : *set) {
      const double t = direction.dot(p - origin);
      if (t < span.low || t > span.high) continue;
      ++span.points;
      if (t < lowest) lowest = t, span.low_point = p;
      if (t > highest) highest = t, span.high_point = p;
    }
  }
  if (span.points < c.min_points / 2) return std::nullopt;
  return span;
}

// Whether the edge goes on beyond `end` (moving along `outward`) but the camera cannot see it:
// the image ends, depth is missing, something nearer hides it, or it runs behind a plane through
// the end that does not end it. The edge joins planes `a` and `b`. Looking past the end:
//  - a plane through the end that the edge would go on in front of is a third face the edge
//    meets (a box's top at the top of its vertical edge): the edge ends;
//  - a plane through the end that the edge would go on behind ends it only if it is a
//    support (terminators: the floor under a box's vertical edge, not the top of a box lying in
//    front of it, which the face beside it goes on below);
//  - another surface nearer than the continuation hides it.
// *ended_by: the plane through the end that ends the edge there, if one does (else unchanged).
bool IsCut(const Eigen::Vector3d& end, const Eigen::Vector3d& outward, int a, int b, const Cloud& cloud,
           const std::vector<int>& plane_of_pixel, const std::vector<DetectedPlane>& planes,
           const CameraIntrinsics& camera, const IntersectionConfig& c, const EdgeTerminators* terminators,
           int* ended_by) {
  // Without terminators every plane is taken for structure: any plane may end an edge.
  auto is_structure = [&](int plane) {
    return terminators == nullptr ||
           (plane < static_cast<int>(terminators->structure.size()) && terminators->structure[plane]);
  };
  // Whether plane `owner`, crossing the edge at its end, ends it: a support neither face of the
  // edge goes on beneath.
  auto terminates = [&](int owner) {
    if (terminators == nullptr) return true;
    const bool structure = is_structure(owner);
    const double cos_tilt = std::cos(terminators->max_tilt_deg * kDegToRad);
    const bool support = planes[owner].plane.normal.dot(terminators->up) > cos_tilt &&
                         outward.dot(terminators->up) < -cos_tilt;
    if (!structure && !support) return false;
    for (int face : {a, b}) {  // an object's faces (the floor is no object's face); a sample suffices
      if (is_structure(face)) continue;
      const std::vector<int>& inliers = planes[face].inliers;
      const size_t stride = std::max<size_t>(1, inliers.size() / 1000);
      int beneath = 0, seen = 0;
      for (size_t k = 0; k < inliers.size(); k += stride, ++seen) {
        const Eigen::Vector3d p = cloud[inliers[k]].getVector3fMap().cast<double>();
        beneath += planes[owner].plane.SignedDistance(p) < -c.support_tolerance;
      }
      if (beneath > c.support_max_share * seen) return false;
    }
    return true;
  };
  // A plane through the edge's line past the end: the edge going on behind it is hidden unless
  // the plane ends it; going on in front of it, the edge met a third face and ended.
  auto hidden_by = [&](int owner) {
    const bool hidden = outward.dot(planes[owner].plane.normal) < 0.0 && !terminates(owner);
    if (!hidden) *ended_by = owner;
    return hidden;
  };
  if (end.z() <= 0.0) return true;
  const double step = end.z() / camera.fx;  // about one pixel at the end's depth [m]
  // The edge's extent is measured on bands up to band_width beside it, which leave the image
  // before the edge line does: an end within that many pixels of the border may be the border's.
  const int margin = c.border_margin + static_cast<int>(std::ceil(c.band_width / step));
  const Eigen::Vector2d end_uv = camera.Project(end);
  if (end_uv.x() < margin || end_uv.y() < margin || end_uv.x() >= camera.width - margin ||
      end_uv.y() >= camera.height - margin) {
    return true;
  }
  // The pixel k steps past the end, at least `border` pixels inside the image; -1 if none.
  auto pixel_past = [&](int k, int border, Eigen::Vector3d* x) {
    *x = end + (k * step) * outward;
    if (x->z() <= 0.0) return -1;
    const Eigen::Vector2d uv = camera.Project(*x);
    const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
    if (u < border || v < border || u >= camera.width - border || v >= camera.height - border) return -1;
    return v * camera.width + u;
  };
  Eigen::Vector3d x;
  // A pixel without depth past the end shows nothing. Before the camera has seen past the end it
  // may be one of the edge's faces going on, seen at a grazing angle: then the end is cut. Where
  // both faces are seen more squarely than grazing_angle_deg, such a face would have depth, and the
  // pixel is the sensor's dropout at the depth edge; the pixels with depth decide, and without
  // any (a shadow band) the end is cut.
  const double cos_grazing = std::cos(c.grazing_angle_deg * kDegToRad);
  auto grazing = [&](const Eigen::Vector3d& ray) {
    for (int f : {a, b}) {
      if (std::abs(planes[f].plane.normal.dot(ray)) < cos_grazing * ray.norm()) return true;
    }
    return false;
  };
  bool seen_past = false;  // something with depth beyond the end, off the edge's faces
  int without_depth = 0;
  for (int k = 0; k <= c.cut_search; ++k) {
    const int i = pixel_past(k, c.border_margin, &x);
    if (i < 0) return true;
    if (k < 2) continue;  // the end pixel itself and its neighbour are on the edge
    if (!IsValidPoint(cloud[i])) {
      if (!seen_past && grazing(x)) return true;
      ++without_depth;
      continue;
    }
    const int owner = plane_of_pixel[i];
    const Eigen::Vector3d seen(cloud[i].x, cloud[i].y, cloud[i].z);
    const bool through = owner >= 0 && owner != a && owner != b &&
                         std::abs(planes[owner].plane.SignedDistance(end)) < 2.0 * c.d_thresh &&
                         (seen - end).norm() < c.end_max_distance;
    if (through) return hidden_by(owner);
    if (owner == a || owner == b) continue;  // the edge's own face cannot hide it
    if (cloud[i].z < x.z() - c.occluder_min_gap) return true;
    seen_past = true;
  }
  if (without_depth > 0 && !seen_past) return true;
  // One of the edge's own faces (not the floor, which goes on past an object's bottom edge) runs
  // on along the line past the end, up to another plane through the line or something nearer,
  // or for face_run_length: the other face stopped there without a corner, so something hides it
  // (a box standing on it). Shorter runs that end in the background are the noise of where a
  // face's last pixels end.
  // Where the edge goes on unseen for unseen_run_length, the end is cut too: a surface on the
  // line itself that no plane took (a strip of a face the segmenter left beside the other face's
  // last pixels), or a face running on past the end into missing depth, so that where it ends is
  // never seen.
  const int run = static_cast<int>(std::ceil(c.face_run_length / step));
  int unsegmented = 0;  // pixels of a surface on the line that no plane took, so far
  for (int k = 2; k <= run; ++k) {
    const int i = pixel_past(k, 0, &x);
    if (i < 0) return false;
    const int owner = plane_of_pixel[i];
    if ((owner == a || owner == b) && !is_structure(owner)) continue;
    const bool valid = IsValidPoint(cloud[i]);
    if (owner < 0 && valid && (cloud[i].getVector3fMap().cast<double>() - x).norm() < c.occluder_min_gap) {
      ++unsegmented;
      continue;
    }
    if (unsegmented * step >= c.unseen_run_length) return true;
    if (!valid && (k - 2) * step >= c.unseen_run_length) return true;
    if (k == 2 || !valid) return false;  // no run, or a short one into missing depth
    if (owner >= 0 && std::abs(planes[owner].plane.SignedDistance(x)) < c.occluder_min_gap) {
      return hidden_by(owner);  // as at the end itself
    }
    return cloud[i].z < x.z() - c.occluder_min_gap;  // a nearer surface, or the background
  }
  return run >= 2;
}

// Free space: where the camera sees past the line by more than occluder_min_gap, the edge is not
// there (its last points are strays a nearly coplanar neighbour lent one of the planes, as the
// side of a box stacked flush under another). An end with free_space_min_run pixels of such a
// stretch moves in to the first point of the line the camera does not see past; a shorter one
// is where a face's last noisy pixels end. [low, high] is the edge along the line [m].
void PullEndsOutOfFreeSpace(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, const Cloud& cloud,
                            const CameraIntrinsics& camera, const IntersectionConfig& c, double* low, double* high) {
  auto seen_past = [&](double t) {
    const Eigen::Vector3d x = origin + t * direction;
    if (x.z() <= 0.0) return false;
    const Eigen::Vector2d uv = camera.Project(x);
    const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
    if (u < 0 || v < 0 || u >= camera.width || v >= camera.height) return false;
    const auto& p = cloud[v * camera.width + u];
    return IsValidPoint(p) && p.z > x.z() + c.occluder_min_gap;
  };
  for (double* end : {high, low}) {
    const double inward = end == high ? -1.0 : 1.0;
    double t = *end;
    int run = 0;
    while (t >= *low && t <= *high && seen_past(t)) {
      t += inward * std::max(1e-4, (origin + t * direction).z() / camera.fx);  // about a pixel
      ++run;
    }
    if (run >= c.free_space_min_run) *end = std::clamp(t, *low, *high);
  }
}

// The point on three planes, if their normals' |determinant| is at least `min_determinant`.
std::optional<Eigen::Vector3d> CornerOf(const Plane& a, const Plane& b, const Plane& c, double min_determinant) {
  Eigen::Matrix3d N;
  N << a.normal.transpose(), b.normal.transpose(), c.normal.transpose();
  if (std::abs(N.determinant()) < min_determinant) return std::nullopt;
  return Eigen::Vector3d(N.partialPivLu().solve(-Eigen::Vector3d(a.offset, b.offset, c.offset)));
}

// The hidden edges (IntersectionConfig::hidden_edges) among `planes`, given the seen `edges`.
void AddHiddenEdges(const std::vector<DetectedPlane>& planes, const Cloud& cloud, const std::vector<int>& plane_of_pixel,
                    const CameraIntrinsics& camera, const IntersectionConfig& c, const EdgeTerminators* terminators,
                    std::vector<PlaneEdge>* edges) {
  const int n = static_cast<int>(planes.size());
  const size_t seen = edges->size();
  std::vector<int> edge_of(static_cast<size_t>(n) * n, -1);
  for (size_t k = 0; k < seen; ++k) {
    const PlaneEdge& e = (*edges)[k];
    edge_of[e.plane_a * n + e.plane_b] = edge_of[e.plane_b * n + e.plane_a] = static_cast<int>(k);
  }
  auto is_structure = [&](int p) {
    return terminators != nullptr && p < static_cast<int>(terminators->structure.size()) && terminators->structure[p];
  };
  // At most about 1000 of a plane's inliers, evenly spread.
  auto sample = [&](const DetectedPlane& face) {
    std::vector<Eigen::Vector3d> points;
    const size_t stride = std::max<size_t>(1, face.inliers.size() / 1000);
    for (size_t k = 0; k < face.inliers.size(); k += stride) points.push_back(PointAt(cloud, face.inliers[k]));
    return points;
  };
  auto mostly_behind = [&](const std::vector<Eigen::Vector3d>& face, const Plane& other) {
    int in_front = 0;
    for (const Eigen::Vector3d& p : face) in_front += other.SignedDistance(p) > c.support_tolerance;
    return in_front <= c.support_max_share * face.size();
  };
  // Whether the line from `from` (an end of the seen edge between planes p and q) to `to` runs
  // behind a nearer surface: from the second pixel past `from` on (the first are the end's own),
  // first perhaps p's or q's own pixels on the line (a face running on, which cut the end; or a
  // surface there no plane took, as IsCut's unsegmented run), then,
  // up to `to` included, pixels all nearer than the line by occluder_min_gap, fewer than
  // 1 - hidden_min_depth_share of them without depth. False where the line leaves the image.
  auto hidden_along = [&](const Eigen::Vector3d& from, const Eigen::Vector3d& to, int p, int q) {
    const double length = (to - from).norm();
    if (from.z() <= 0.0 || to.z() <= 0.0 || length <= 2.0 * from.z() / camera.fx) return false;
    const Eigen::Vector3d direction = (to - from) / length;
    bool occluded = false;  // past the own faces' run
    int pixels = 0, with_depth = 0;
    for (double t = 2.0 * from.z() / camera.fx;; t += std::max(1e-4, (from + t * direction).z() / camera.fx)) {
      const Eigen::Vector3d x = from + std::min(t, length) * direction;
      const Eigen::Vector2d uv = camera.Project(x);
      const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
      if (u < c.border_margin || v < c.border_margin || u >= camera.width - c.border_margin ||
          v >= camera.height - c.border_margin) {
        return false;
      }
      const int i = v * camera.width + u;
      const auto& point = cloud[i];
      const bool valid = IsValidPoint(point);
      if (!occluded && valid && (plane_of_pixel[i] == p || plane_of_pixel[i] == q || plane_of_pixel[i] < 0) &&
          std::abs(point.z - x.z()) < c.occluder_min_gap) {
        if (t >= length) return false;  // the faces run on to the corner: it is seen
        continue;
      }
      occluded = occluded || valid;  // a pixel without depth does not end the faces' run
      ++pixels;
      if (valid) {
        ++with_depth;
        if (point.z >= x.z() - c.occluder_min_gap) return false;  // seen: on the line or past it
      }
      if (t >= length) break;
    }
    return with_depth >= c.hidden_min_depth_share * pixels;
  };
  const double max_cos = std::cos(c.min_angle_deg * kDegToRad);
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      const Plane& pa = planes[a].plane;
      const Plane& pb = planes[b].plane;
      if (edge_of[a * n + b] >= 0 || is_structure(a) || is_structure(b) || std::abs(pa.normal.dot(pb.normal)) > max_cos) {
        continue;
      }
      // The corners the hidden edge is seen to reach: one per third plane k that passes.
      std::vector<std::pair<int, Eigen::Vector3d>> corners;
      for (int k = 0; k < n; ++k) {
        const int e1 = edge_of[a * n + k], e2 = edge_of[b * n + k];
        if (e1 < 0 || e2 < 0) continue;
        const std::optional<Eigen::Vector3d> at = CornerOf(pa, pb, planes[k].plane, c.hidden_min_determinant);
        if (!at) continue;
        const Eigen::Vector3d& corner = *at;
        // Each seen edge's end toward the corner is cut, and the corner lies past it, within reach,
        // hidden all the way.
        bool hidden = true;
        for (const int e : {e1, e2}) {
          const PlaneEdge& edge = (*edges)[e];
          const double s = (corner - edge.start).dot(edge.direction);
          const bool toward_end = s > 0.5 * edge.length;
          const double past = toward_end ? s - edge.length : -s;
          hidden = hidden && (toward_end ? edge.end_cut : edge.start_cut) && past > 0.0 && past <= c.hidden_max_reach &&
                   hidden_along(toward_end ? edge.end : edge.start, corner, edge.plane_a, edge.plane_b);
        }
        if (hidden) corners.emplace_back(k, corner);
      }
      if (corners.empty()) continue;
      const std::vector<Eigen::Vector3d> points_a = sample(planes[a]), points_b = sample(planes[b]);
      if (!mostly_behind(points_a, pb) || !mostly_behind(points_b, pa)) continue;  // not a solid's corner
      PlaneEdge edge;
      edge.plane_a = a;
      edge.plane_b = b;
      edge.convex = true;
      edge.hidden = true;
      edge.direction = pa.normal.cross(pb.normal).normalized();
      if (corners.size() >= 2) {
        // Two corners (the top's and the floor's): the edge runs between the two farthest apart,
        // both ends known.
        double low = 0.0, high = 0.0;
        Eigen::Vector3d low_point = corners[0].second, high_point = corners[0].second;
        for (const auto& [k, corner] : corners) {
          const double t = edge.direction.dot(corner - corners[0].second);
          if (t < low) low = t, low_point = corner;
          if (t > high) high = t, high_point = corner;
        }
        edge.start = low_point;
        edge.end = high_point;
        edge.length = high - low;
      } else {
        // One corner: the edge leaves it toward the faces, as far as both reach from the third
        // plane (their 99th percentile: a stray point does not lengthen it), measured as the
        // distance from that plane over the edge's slope to it, not along the edge: a face a few
        // degrees off would tilt the edge, and a face's points far from it would move along it.
        const Plane& pk = planes[corners[0].first].plane;
        std::vector<double> height_a, height_b;
        for (const Eigen::Vector3d& p : points_a) height_a.push_back(pk.SignedDistance(p));
        for (const Eigen::Vector3d& p : points_b) height_b.push_back(pk.SignedDistance(p));
        const double side = Percentile(height_a, 0.5) + Percentile(height_b, 0.5) < 0.0 ? -1.0 : 1.0;
        for (double& h : height_a) h *= side;
        for (double& h : height_b) h *= side;
        if (side * edge.direction.dot(pk.normal) < 0.0) edge.direction = -edge.direction;
        edge.length = std::min(Percentile(height_a, 0.99), Percentile(height_b, 0.99)) /
                      std::abs(edge.direction.dot(pk.normal));
        edge.start = corners[0].second;
        edge.end = edge.start + edge.length * edge.direction;
        edge.end_cut = true;  // where the faces' points end is not where the edge is seen to end
      }
      if (edge.length < c.min_length) continue;
      edges->push_back(edge);
      // Faces a and b go on to their hidden edge: a seen edge of either that ends short of the
      // corner it would make with it (a bottom edge along the floor ending where the occluder's
      // shadow begins, floor seen past it) is not seen to end there: it is cut.
      for (size_t k = 0; k < seen; ++k) {
        PlaneEdge& other = (*edges)[k];
        if (other.plane_a != a && other.plane_a != b && other.plane_b != a && other.plane_b != b) continue;
        const int m = other.plane_a == a || other.plane_a == b ? other.plane_b : other.plane_a;
        if (m == a || m == b) continue;
        const std::optional<Eigen::Vector3d> meet = CornerOf(pa, pb, planes[m].plane, c.hidden_min_determinant);
        if (!meet) continue;
        const double s = (*meet - other.start).dot(other.direction);
        if (s > 0.5 * other.length && s - other.length > c.d_thresh) other.end_cut = true;
        if (s <= 0.5 * other.length && -s > c.d_thresh) other.start_cut = true;
      }
    }
  }
}

// The planes' fringes (IntersectionConfig::fringe_px): ring by ring out from the planes' pixels,
// each pixel with depth that no plane took goes to the nearest of its 4-neighbours' planes within
// the fringe distance of it. A ring's pixels are given their planes only after all of them are
// decided, so the result does not depend on the order of visits. plane_of_pixel (-1: no plane)
// gets the fringes' pixels too; each plane's fringe comes out sorted by pixel index.
std::vector<std::vector<int>> Fringes(const std::vector<DetectedPlane>& planes, const Cloud& cloud,
                                      const IntersectionConfig& c, std::vector<int>* plane_of_pixel) {
  std::vector<std::vector<int>> fringe(planes.size());
  if (c.fringe_px <= 0) return fringe;
  std::vector<int>& owner = *plane_of_pixel;
  const int w = static_cast<int>(cloud.width), h = static_cast<int>(cloud.height);
  auto neighbours = [&](int i, int u, int v, auto&& visit) {
    if (u > 0) visit(i - 1);
    if (u + 1 < w) visit(i + 1);
    if (v > 0) visit(i - w);
    if (v + 1 < h) visit(i + w);
  };
  // The first ring: free pixels beside a plane's, with depth.
  std::vector<int> ring, next;
  for (int v = 0; v < h; ++v) {
    for (int u = 0, i = v * w; u < w; ++u, ++i) {
      if (owner[i] != -1) continue;
      bool beside = false;
      neighbours(i, u, v, [&](int j) { beside = beside || owner[j] >= 0; });
      if (beside && IsValidPoint(cloud[i])) ring.push_back(i);
    }
  }
  std::vector<std::pair<int, int>> taken;  // pixel, plane: this ring's
  for (int step = 0; step < c.fringe_px && !ring.empty(); ++step) {
    taken.clear();
    for (const int i : ring) {
      const Eigen::Vector3d p = PointAt(cloud, i);
      int best = -1;
      double best_distance = GrowsWithDepth(c.fringe_distance_base, c.fringe_distance_quadratic, p.z());
      neighbours(i, i % w, i / w, [&](int j) {
        const int k = owner[j];
        if (k < 0 || k == best) return;
        const double d = std::abs(planes[k].plane.SignedDistance(p));
        if (d < best_distance || (d == best_distance && k < best)) best = k, best_distance = d;
      });
      if (best >= 0) taken.emplace_back(i, best);
    }
    for (const auto& [i, k] : taken) {
      owner[i] = k;
      fringe[k].push_back(i);
    }
    next.clear();
    for (const auto& [i, k] : taken) {
      neighbours(i, i % w, i / w, [&](int j) {
        if (owner[j] == -1 && IsValidPoint(cloud[j])) {
          owner[j] = -2;  // queued once
          next.push_back(j);
        }
      });
    }
    for (const int j : next) owner[j] = -1;
    ring.swap(next);
  }
  for (std::vector<int>& f : fringe) std::sort(f.begin(), f.end());
  return fringe;
}

}  // namespace

std::vector<PlaneEdge> FindIntersections(const std::vector<DetectedPlane>& planes, const Cloud& cloud,
                                         const CameraIntrinsics& camera, const IntersectionConfig& c,
                                         const EdgeTerminators* terminators) {
  std::vector<Box3> boxes(planes.size());
  std::vector<Window> pixels(planes.size(), Window{1 << 30, -1, 1 << 30, -1});
  std::vector<int> plane_of_pixel(cloud.size(), -1);
  const int w = static_cast<int>(cloud.width);
  for (size_t k = 0; k < planes.size(); ++k) {
    boxes[k] = InlierBounds(cloud, planes[k]);
    const std::vector<int>& inliers = planes[k].inliers;
    for (int i : inliers) plane_of_pixel[i] = static_cast<int>(k);
    // Sorted by pixel index: each row's inliers are one run, whose first and last give its
    // columns (found by bisection, not by visiting the run); the first and last give the rows.
    Window& win = pixels[k];
    for (auto it = inliers.begin(); it != inliers.end();) {
      const int row_start = (*it / w) * w;
      const auto row_end = std::lower_bound(it, inliers.end(), row_start + w);
      win.u0 = std::min(win.u0, *it - row_start), win.u1 = std::max(win.u1, *(row_end - 1) - row_start);
      it = row_end;
    }
    if (!inliers.empty()) {
      win.v0 = inliers.front() / w;
      win.v1 = inliers.back() / w;
    }
  }
  // The fringes count as their planes' pixels for the edges (and in plane_of_pixel); the planes
  // themselves are left as they are.
  const std::vector<std::vector<int>> fringe = Fringes(planes, cloud, c, &plane_of_pixel);
  for (size_t k = 0; k < planes.size(); ++k) {
    for (const int i : fringe[k]) {
      boxes[k].Extend(PointAt(cloud, i));
      Window& win = pixels[k];
      win.u0 = std::min(win.u0, i % w), win.u1 = std::max(win.u1, i % w);
      win.v0 = std::min(win.v0, i / w), win.v1 = std::max(win.v1, i / w);
    }
  }
  // Plane k's pixel box grown by band_width seen at its nearest depth, clipped to the image.
  auto grown = [&](size_t k) {
    const int margin = 2 + static_cast<int>(std::ceil(c.band_width * camera.fx / std::max(boxes[k].low.z(), 0.1)));
    Window win = pixels[k];
    win.u0 = std::max(0, win.u0 - margin), win.u1 = std::min(w - 1, win.u1 + margin);
    win.v0 = std::max(0, win.v0 - margin), win.v1 = std::min(static_cast<int>(cloud.height) - 1, win.v1 + margin);
    return win;
  };
  const double max_cos = std::cos(c.min_angle_deg * kDegToRad);
  const double far = std::max(c.d_thresh, c.band_width);  // CollectEdgePoints looks no farther from the other plane
  std::vector<PlaneEdge> edges;
  // Each pair's points, and CollectEdgePoints' scratch: emptied for each pair, but their memory
  // kept (growing them pair after pair cost about a tenth of the stage).
  std::vector<Eigen::Vector3d> points_a, points_b, band_a, band_b;
  std::vector<double> distance, sorted;
  for (size_t a = 0; a < planes.size(); ++a) {
    for (size_t b = a + 1; b < planes.size(); ++b) {
      const Plane& pa = planes[a].plane;
      const Plane& pb = planes[b].plane;
      if (std::abs(pa.normal.dot(pb.normal)) > max_cos || !boxes[a].Overlaps(boxes[b], c.d_thresh)) continue;
      // Neither plane has a point within `far` of the other (so no edge point and no band point,
      // and SharedSpan finds nothing) when its box lies wholly on one side of the other's slab.
      if (!BoxMeetsSlab(boxes[a], pb, far) || !BoxMeetsSlab(boxes[b], pa, far)) continue;
      points_a.clear(), points_b.clear(), band_a.clear(), band_b.clear();
      // The planes whose points come near both (the others are too far to have lent a pixel).
      std::vector<const DetectedPlane*> nearby;
      for (size_t k = 0; k < planes.size(); ++k) {
        if (boxes[k].Overlaps(boxes[a], c.band_width) && boxes[k].Overlaps(boxes[b], c.band_width)) {
          nearby.push_back(&planes[k]);
        }
      }
      CollectEdgePoints(planes[a], fringe[a], planes[b], nearby, grown(b), cloud, c, &points_a, &band_a, &distance, &sorted);
      CollectEdgePoints(planes[b], fringe[b], planes[a], nearby, grown(a), cloud, c, &points_b, &band_b, &distance, &sorted);
      if (static_cast<int>(points_a.size() + points_b.size()) < c.min_points) continue;

      // The intersection line: direction n_a x n_b through the point nearest the origin.
      const Eigen::Vector3d direction = pa.normal.cross(pb.normal).normalized();
      Eigen::Matrix3d A;
      A << pa.normal.transpose(), pb.normal.transpose(), direction.transpose();
      const Eigen::Vector3d origin = A.partialPivLu().solve(Eigen::Vector3d(-pa.offset, -pb.offset, 0.0));
      const std::optional<Interval> band = SharedSpan(band_a, band_b, origin, direction, c);
      if (!band) continue;
      // The edge points (eqs. 2-5) within the stretch both planes cover.
      Interval span = *band;
      span.points = 0;
      double lowest = 1e30, highest = -1e30;
      for (const auto* set : {&points_a, &points_b}) {
        for (const Eigen::Vector3d& p : *set) {
          const double t = direction.dot(p - origin);
          if (t < band->low || t > band->high) continue;
          ++span.points;
          if (t < lowest) lowest = t, span.low_point = p;
          if (t > highest) highest = t, span.high_point = p;
        }
      }
      PullEndsOutOfFreeSpace(origin, direction, cloud, camera, c, &span.low, &span.high);
      if (span.points < c.min_points || span.high - span.low < c.min_length) continue;

      PlaneEdge edge;
      edge.plane_a = static_cast<int>(a);
      edge.plane_b = static_cast<int>(b);
      edge.points = span.points;
      edge.direction = direction;
      edge.start = origin + span.low * direction;
      edge.end = origin + span.high * direction;
      edge.length = span.high - span.low;
      // Eq. (6): the two farthest edge points span the diagonal of a cylinder of radius d_thresh.
      const double diagonal = (span.high_point - span.low_point).norm();
      edge.length_eq6 = std::sqrt(std::max(0.0, diagonal * diagonal - 4.0 * c.d_thresh * c.d_thresh));
      edge.convex = MostlyBehind(band_a, pb, origin, direction, span.low, span.high) &&
                    MostlyBehind(band_b, pa, origin, direction, span.low, span.high);
      const int ia = static_cast<int>(a), ib = static_cast<int>(b);
      int start_by = -1, end_by = -1;
      edge.start_cut = IsCut(edge.start, -direction, ia, ib, cloud, plane_of_pixel, planes, camera, c, terminators, &start_by);
      edge.end_cut = IsCut(edge.end, direction, ia, ib, cloud, plane_of_pixel, planes, camera, c, terminators, &end_by);
      // An end that a plane through it ends is where the line meets that plane: the faces' last
      // pixels before it (within the inlier distance of both) went to neither face's band.
      if (c.end_on_ending_plane) {
        for (const auto& [by, t] : {std::pair<int, double*>{start_by, &span.low}, std::pair<int, double*>{end_by, &span.high}}) {
          if (by < 0) continue;
          const Plane& ending = planes[by].plane;
          const double slope = ending.normal.dot(direction);
          if (std::abs(slope) < std::sin(c.min_angle_deg * kDegToRad)) continue;
          const double at = -ending.SignedDistance(origin) / slope;
          if (std::abs(at - *t) <= c.end_on_ending_plane_max) *t = at;
        }
        if (span.high - span.low < c.min_length) continue;
        edge.start = origin + span.low * direction;
        edge.end = origin + span.high * direction;
        edge.length = span.high - span.low;
      }
      edges.push_back(edge);
    }
  }
  if (c.hidden_edges) AddHiddenEdges(planes, cloud, plane_of_pixel, camera, c, terminators, &edges);
  return edges;
}

}  // namespace planemap
