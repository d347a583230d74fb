#pragma once
// Closed boxes (outward-facing quads) for test scenes.

#include "penumbra/geometry/quaternion.h"
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

// Two flat boxes turned about tilted axes, one above the other (objects "lower" and "upper"),
// for a room 4 x 4 x 3 lit from its ceiling: where their shadows overlap, EEE events of edges of
// both boxes cross the floor.
inline void addTiltedBoxPair(SceneBuilder& b, const std::string& material) {
  const Quaternion turn = Quaternion::fromAxisAngle(normalize(Vec3{1, 2, 0.5}), 0.7);
  const Quaternion other = Quaternion::fromAxisAngle(normalize(Vec3{-1, 0.5, 2}), 1.1);
  for (Polygon3 face : boxFaces({-0.35, -0.25, -0.1}, {0.35, 0.25, 0.1})) {
    Polygon3 upper = face;
    for (Vec3& v : face) v = turn.toMatrix() * v + Vec3{2.0, 1.9, 1.2};
    for (Vec3& v : upper) v = other.toMatrix() * v + Vec3{2.1, 2.0, 2.0};
    b.addPolygon(material, face, "lower");
    b.addPolygon(material, upper, "upper");
  }
}

}  // namespace penumbra::test
