#pragma once
// The ranges of a parameter in [0, 1] where a property holds, when it can change only at known
// breaks: decided at the middle of each range between consecutive breaks, touching ranges merged.
// Used for the critical lines of EV and EEE surfaces, whose existence changes where a line passes
// through a feature's endpoint.

#include <algorithm>
#include <array>
#include <vector>

namespace penumbra {

template <class Holds>
std::vector<std::array<double, 2>> rangesBetween(std::vector<double> breaks, Holds&& holds) {
  std::sort(breaks.begin(), breaks.end());
  std::vector<std::array<double, 2>> ranges;
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    if (breaks[k + 1] <= breaks[k]) continue;
    if (!holds(0.5 * (breaks[k] + breaks[k + 1]))) continue;
    if (!ranges.empty() && ranges.back()[1] == breaks[k])
      ranges.back()[1] = breaks[k + 1];
    else
      ranges.push_back({breaks[k], breaks[k + 1]});
  }
  return ranges;
}

}  // namespace penumbra
