#pragma once
// Small statistics on samples.
#include <algorithm>
#include <vector>

namespace planemap {

// The q-quantile (q in [0, 1]) of `sorted` (ascending), interpolated linearly between order
// statistics (numpy's default); 0 for no values.
inline double SortedPercentile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  const double rank = std::clamp(q, 0.0, 1.0) * static_cast<double>(sorted.size() - 1);
  const size_t below = static_cast<size_t>(rank);
  const size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (rank - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

// The same of `values` in any order.
inline double Percentile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  return SortedPercentile(values, q);
}

}  // namespace planemap
