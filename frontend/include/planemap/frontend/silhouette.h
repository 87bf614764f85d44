#pragma once
// Where a plane's surface ends against background: its silhouette pixels. At such a pixel the
// surface stops and the camera sees past it, so the solid's neighbouring face (out of sight, or
// seen edge-on) passes within about a pixel of it. The tracker uses these to fix, near a box, the
// direction no plane in view fixes (tracker.h, TrackingConfig::silhouette_*).
#include <vector>

#include "planemap/frontend/organized_cloud.h"

namespace planemap {

// Inlier pixels of one plane (indices into the organized `cloud`) with a 4-neighbour direction in
// which, after at most `max_missing` pixels without depth (sensors drop pixels at depth
// discontinuities), the first pixel with depth is not an inlier and lies at least `min_gap` [m]
// farther along the optical axis. A pixel with a neighbouring non-inlier that is nearer, within
// min_gap, or without depth for longer (an occluder, an unsegmented strip of the same surface, a
// hole) is not one, nor is a pixel whose search runs off the image: the surface may go on there.
std::vector<int> SilhouettePixels(const Cloud& cloud, const std::vector<int>& inliers, double min_gap,
                                  int max_missing);

}  // namespace planemap
