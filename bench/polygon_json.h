#pragma once
// Polygons as JSON scene text, for the benches that generate scenes.

#include <algorithm>
#include <array>
#include <sstream>
#include <string>
#include <vector>

namespace penumbra::bench {

using Corners = std::vector<std::array<double, 3>>;

// `[[x,y,z],...]` with `precision` significant digits (the stream's default: 6).
inline std::string cornersJson(const Corners& corners, int precision = 6) {
  std::ostringstream out;
  out.precision(precision);
  out << '[';
  for (size_t i = 0; i < corners.size(); ++i)
    out << (i ? "," : "") << '[' << corners[i][0] << ',' << corners[i][1] << ',' << corners[i][2]
        << ']';
  return out.str() + ']';
}

// The same polygon facing the other way.
inline Corners reversed(Corners corners) {
  std::reverse(corners.begin(), corners.end());
  return corners;
}

}  // namespace penumbra::bench
