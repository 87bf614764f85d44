#pragma once
// Small statistics on samples.
#include <algorithm>
#include <vector>

namespace planemap {

// The q-quantile (q in [0, 1]) of `values`, interpolated linearly between order statistics
// (numpy's default); 0 for no values.
inline double Percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const size_t below = static_cast<size_t>(rank);
  const size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (rank - static_cast<double>(below)) * (values[above] - values[below]);
}

}  // namespace planemap
