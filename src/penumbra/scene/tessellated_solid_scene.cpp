#include "penumbra/scene/tessellated_solid_scene.h"

#include <cmath>
#include <sstream>
#include <vector>

#include "penumbra/geometry/vec3.h"

namespace penumbra {

namespace {

void writePoint(std::ostream& out, const Vec3& p) {
  out << '[' << p.x << ',' << p.y << ',' << p.z << ']';
}

void writePolygon(std::ostream& out, const std::vector<Vec3>& loop) {
  out << '[';
  for (size_t i = 0; i < loop.size(); ++i) {
    if (i) out << ',';
    writePoint(out, loop[i]);
  }
  out << ']';
}

}  // namespace

std::string tessellatedSolidSceneJson(const TessellatedSolidOptions& options) {
  const int n = options.sides;
  constexpr double kRadius = 0.3, kStart = 0.1;
  const auto rim = [&](int k, double y) {
    const double angle = kStart + 2 * M_PI * k / n;
    return Vec3{0.5 + kRadius * std::cos(angle), y, 0.5 + kRadius * std::sin(angle)};
  };
  std::ostringstream json;
  json.precision(17);
  json << R"({"penumbra": 1, "frames": 1,
  "materials": {"white": {"reflectance": [0.7, 0.7, 0.7]},
                "lamp": {"reflectance": [0, 0, 0], "emission": [10, 10, 10]}},
  "objects": [
    {"name": "floor", "material": "white", "polygons": [[[0,0,1],[1,0,1],[1,0,0],[0,0,0]]]},
    {"name": "lamp", "material": "lamp",
     "polygons": [[[0.4,1,0.4],[0.6,1,0.4],[0.6,1,0.6],[0.4,1,0.6]]]},
    {"name": ")"
       << (options.cylinder ? "cylinder" : "disc") << R"(", "material": "white", "polygons": [)";
  // Counter-clockwise seen from the front: x × z = −y, so the rim in increasing angle faces down
  // and its reverse up; a side (up, then along increasing angle) faces out.
  const double low = options.cylinder ? 0.45 : 0.5, high = 0.55;
  std::vector<Vec3> bottom;
  for (int k = 0; k < n; ++k) bottom.push_back(rim(k, low));
  writePolygon(json, bottom);
  if (options.cylinder) {
    std::vector<Vec3> top;
    for (int k = n - 1; k >= 0; --k) top.push_back(rim(k, high));
    json << ',';
    writePolygon(json, top);
    for (int k = 0; k < n; ++k) {  // outward sides
      json << ',';
      writePolygon(json, {rim(k, low), rim(k, high), rim(k + 1, high), rim(k + 1, low)});
    }
  }
  json << "]}]}";
  return json.str();
}

}  // namespace penumbra
