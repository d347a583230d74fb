#pragma once
// Summaries the benchmarks print: the median of timings (robust to a slow outlier), the mean of
// counts, percentiles of errors.

#include <algorithm>
#include <vector>

namespace penumbra::bench {

inline double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// The q-quantile (0 <= q <= 1), interpolated linearly between the sorted values; 0 when empty.
inline double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const double at = q * double(values.size() - 1);
  const size_t i = size_t(at);
  const double t = at - double(i);
  return i + 1 < values.size() ? values[i] * (1 - t) + values[i + 1] * t : values[i];
}

inline double mean(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return v.empty() ? 0 : sum / double(v.size());
}

}  // namespace penumbra::bench
