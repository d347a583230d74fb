// Fuzz target: the probe points file (DESIGN.md §6, src/app/cli/points_file.h: `x y z nx ny nz`
// per line, blank lines and `#` comments ignored). Bad lines must be InputErrors naming the file;
// the points it accepts must keep the reader's promises: finite positions within kMaxCoordinate,
// unit normals, the raw normal echoed as written, line numbers increasing.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "fuzz_outcome.h"
#include "fuzz_temp_dir.h"
#include "penumbra/scene/scene_loader.h"
#include "points_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace penumbra;
  using fuzz::reportFinding;
  const fuzz::FuzzTempDir& dir = fuzz::FuzzTempDir::instance();
  const std::string path =
      dir.write("points.txt", std::string_view(reinterpret_cast<const char*>(data), size));
  std::vector<cli::ProbePoint> points;
  if (!fuzz::succeedsOrRejects(path, [&] { points = cli::readPointsFile(path); })) return 0;
  int previousLine = 0;
  for (const cli::ProbePoint& p : points) {
    const std::string where = "point of line " + std::to_string(p.line);
    if (p.line <= previousLine) reportFinding(where + ": line numbers do not increase");
    previousLine = p.line;
    if (!p.position.isFinite() || !p.normal.isFinite() || !p.rawNormal.isFinite())
      reportFinding(where + ": not finite");
    for (double c : {p.position.x, p.position.y, p.position.z})
      if (!(std::abs(c) <= kMaxCoordinate)) reportFinding(where + ": beyond kMaxCoordinate");
    // A normalised vector's length is 1 within a few ulps, however large or small the input.
    if (!(std::abs(length(p.normal) - 1) <= 1e-12)) reportFinding(where + ": normal not unit");
    if (!(dot(p.normal, p.rawNormal) > 0)) reportFinding(where + ": normal turned around");
  }
  return 0;
}
