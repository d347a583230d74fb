#pragma once
// Closed boxes (outward-facing quads) for test scenes.

#include "support/scene_builder.h"

namespace penumbra::test {

inline std::vector<Polygon3> boxFaces(const Vec3& lo, const Vec3& hi) {
  const double x0 = lo.x, y0 = lo.y, z0 = lo.z, x1 = hi.x, y1 = hi.y, z1 = hi.z;
  return {{{x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}},
          {{x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}},
          {{x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1}},
          {{x0, y1, z0}, {x0, y1, z1}, {x1, y1, z1}, {x1, y1, z0}},
          {{x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, {x0, y1, z0}},
          {{x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}}};
}

inline void addBox(SceneBuilder& b, const std::string& material, const std::string& name,
                   const Vec3& lo, const Vec3& hi) {
  for (const Polygon3& f : boxFaces(lo, hi)) b.addPolygon(material, f, name);
}

// The inside of a box: faces pointing inwards (a closed room).
inline void addRoom(SceneBuilder& b, const std::string& material, const Vec3& lo, const Vec3& hi) {
  for (Polygon3 f : boxFaces(lo, hi)) {
    std::reverse(f.begin(), f.end());
    b.addPolygon(material, f, "room");
  }
}

}  // namespace penumbra::test
