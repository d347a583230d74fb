#include "points_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "penumbra/base/input_error.h"
#include "penumbra/base/input_file.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra::cli {

std::vector<ProbePoint> readPointsFile(const std::string& path) {
  std::ifstream in = openInputFile(path, "points file");
  std::vector<ProbePoint> points;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    const auto hash = text.find('#');
    if (hash != std::string::npos) text.resize(hash);
    std::istringstream tokens(text);
    std::vector<double> values;
    std::string token;
    while (tokens >> token) {
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(token.c_str(), &end);
      if (end != token.c_str() + token.size() || errno == ERANGE || !std::isfinite(v))
        throw InputError(path + ":" + std::to_string(line),
                         "'" + token + "' is not a finite number");
      values.push_back(v);
    }
    if (values.empty()) continue;
    if (values.size() != 6)
      throw InputError(path + ":" + std::to_string(line),
                       "expected 6 numbers (x y z nx ny nz), got " + std::to_string(values.size()));
    for (int k = 0; k < 3; ++k)
      if (!(std::abs(values[k]) <= kMaxCoordinate))
        throw InputError(path + ":" + std::to_string(line),
                         "the point lies beyond 1e9 of the origin, where no scene reaches");
    ProbePoint p;
    p.position = {values[0], values[1], values[2]};
    p.rawNormal = {values[3], values[4], values[5]};
    // Scaled by its largest component first: the squared length of (1e-160, 0, 0) underflows to a
    // subnormal that keeps a few bits (the "unit" normal came out 6e-6 too long), and that of
    // (1e300, 1e300, 0) overflows (it was refused as "the zero vector").
    const double largest =
        std::max({std::abs(values[3]), std::abs(values[4]), std::abs(values[5])});
    if (!(largest > 0))
      throw InputError(path + ":" + std::to_string(line), "the normal is the zero vector");
    p.normal = normalize(p.rawNormal / largest);
    p.line = line;
    points.push_back(p);
  }
  return points;
}

}  // namespace penumbra::cli
