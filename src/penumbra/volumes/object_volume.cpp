#include "penumbra/volumes/object_volume.h"

#include <algorithm>
#include <utility>

#include "penumbra/base/check.h"

namespace penumbra {

namespace {

Vec3 ringNormal(const std::vector<int>& ring, const std::vector<Vec3>& vertices) {
  // Newell's normal: robust for non-convex polygons and independent of the starting vertex.
  Vec3 n;
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec3& a = vertices[ring[i]];
    const Vec3& b = vertices[ring[(i + 1) % ring.size()]];
    n += cross(a, b);
  }
  return n;
}

}  // namespace

std::vector<signed char> facingSignature(const OccluderMesh& mesh,
                                         const std::vector<Vec3>& nearVertices, const Vec3& light,
                                         int excludedPolygon) {
  std::vector<signed char> facing(mesh.polygons.size(), 0);
  for (int p = 0; p < int(mesh.polygons.size()); ++p) {
    if (p == excludedPolygon || mesh.triangles[p].empty()) continue;
    const auto& ring = mesh.polygons[p];
    const double side = dot(ringNormal(ring, nearVertices), light - nearVertices[ring[0]]);
    // Edge-on polygons (side == 0) cast no area; leaving them out keeps the signature stable.
    facing[p] = side > 0 ? 1 : (side < 0 ? -1 : 0);
  }
  return facing;
}

ObjectVolume buildObjectVolume(const OccluderMesh& mesh, std::vector<Vec3> nearVertices,
                               const Vec3& light, double baseW, int excludedPolygon) {
  CHECK_EQ(nearVertices.size(), mesh.vertices.size());
  ObjectVolume volume;
  volume.baseW = baseW;
  volume.facing = facingSignature(mesh, nearVertices, light, excludedPolygon);
  const bool closed = mesh.isClosed && excludedPolygon < 0;
  // Whether polygon p is a cap, and its orientation towards the light (+1 input winding).
  auto capSign = [&](int p) -> int {
    const int f = volume.facing[p];
    if (f == 0) return 0;
    return closed ? (f > 0 ? 1 : 0) : f;
  };
  for (int p = 0; p < int(mesh.polygons.size()); ++p) {
    const int sign = capSign(p);
    if (sign == 0) continue;
    for (const auto& t : mesh.triangles[p])
      volume.capTriangles.push_back(sign > 0 ? t : std::array<int, 3>{t[0], t[2], t[1]});
    const auto& ring = mesh.polygons[p];
    const int n = int(ring.size());
    for (int i = 0; i < n; ++i) {
      int a = ring[i], b = ring[(i + 1) % n];
      const int q = mesh.neighbor[p][i];
      // The neighbour's oriented cap runs through (a, b) the other way when it has the same sign
      // (the input windings already run opposite): the two side quads cancel.
      if (q >= 0 && capSign(q) == sign) continue;
      if (sign < 0) std::swap(a, b);
      volume.silhouetteEdges.push_back({a, b});
    }
  }
  volume.baseVertices.resize(nearVertices.size());
  for (size_t i = 0; i < nearVertices.size(); ++i)
    volume.baseVertices[i] = baseVertex(nearVertices[i], light, baseW);
  volume.nearVertices = std::move(nearVertices);
  return volume;
}

void translateLight(ObjectVolume& volume, const Vec3& d) {
  // b/k = v - L + L/k: a light translation d adds (1 - k) d to b, i.e. -(1 - 1/k) d to b/k.
  const Vec3 step = -d * (1 - volume.baseW);
  for (Vec3& b : volume.baseVertices) b += step;
}

void moveOccluder(ObjectVolume& volume, const Transform& delta, const Vec3& light) {
  if (delta.linear.m[0][0] == 1 && delta.linear.m[1][1] == 1 && delta.linear.m[2][2] == 1 &&
      delta.linear.m[0][1] == 0 && delta.linear.m[0][2] == 0 && delta.linear.m[1][0] == 0 &&
      delta.linear.m[1][2] == 0 && delta.linear.m[2][0] == 0 && delta.linear.m[2][1] == 0) {
    // A translation t: near vertices move by t, base vertices by k t (stored b/k: by t).
    const Vec3 t = delta.translation;
    for (Vec3& v : volume.nearVertices) v += t;
    for (Vec3& b : volume.baseVertices) b += t;
    return;
  }
  for (size_t i = 0; i < volume.nearVertices.size(); ++i) {
    volume.nearVertices[i] = delta.applyToPoint(volume.nearVertices[i]);
    volume.baseVertices[i] = baseVertex(volume.nearVertices[i], light, volume.baseW);
  }
}

ObjectVolume reflectedVolume(const ObjectVolume& volume, const Transform& reflection) {
  ObjectVolume out;
  out.baseW = volume.baseW;
  out.facing = volume.facing;
  out.nearVertices.reserve(volume.nearVertices.size());
  for (const Vec3& v : volume.nearVertices) out.nearVertices.push_back(reflection.applyToPoint(v));
  // A homogeneous point (x, w) maps to (A x + t w, w).
  out.baseVertices.reserve(volume.baseVertices.size());
  for (const Vec3& b : volume.baseVertices)
    out.baseVertices.push_back(reflection.linear * b + reflection.translation * volume.baseW);
  const bool flip = reflection.isReflection();
  out.capTriangles = volume.capTriangles;
  out.silhouetteEdges = volume.silhouetteEdges;
  if (flip) {
    for (auto& t : out.capTriangles) std::swap(t[1], t[2]);
    for (auto& e : out.silhouetteEdges) std::swap(e[0], e[1]);
  }
  return out;
}

}  // namespace penumbra
