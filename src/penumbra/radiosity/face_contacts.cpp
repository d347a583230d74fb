#include "penumbra/radiosity/face_contacts.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

// Pairs of polygons in one plane facing each other with overlapping bounds (a box standing on the
// floor, a handle on a drawer). Planes are compared in a canonical orientation (first non-zero
// normal component positive), sorted by offset, so only polygons with nearly equal offsets are
// paired up.
std::vector<std::vector<PolygonId>> faceContacts(const PosedScene& scene) {
  std::vector<std::vector<PolygonId>> contacts(scene.polygons.size());
  const double slack = 1e-9 * std::max(1.0, scene.extent.diagonalLength());
  const auto canonicalOffset = [](const Plane& plane) {
    const Vec3& n = plane.normal;
    const double first = n.x != 0 ? n.x : n.y != 0 ? n.y : n.z;
    return first > 0 ? plane.offset : -plane.offset;
  };
  std::vector<std::pair<double, PolygonId>> order;
  for (const WorldPolygon& p : scene.polygons) order.push_back({canonicalOffset(p.plane), p.id});
  std::sort(order.begin(), order.end());
  for (size_t i = 0; i < order.size(); ++i)
    for (size_t j = i + 1; j < order.size() && order[j].first - order[i].first <= 2 * slack; ++j) {
      const WorldPolygon& a = scene.polygons[order[i].second];
      const WorldPolygon& b = scene.polygons[order[j].second];
      if (dot(a.plane.normal, b.plane.normal) > -1 + 1e-9) continue;
      if (!a.bounds.expanded(slack).overlaps(b.bounds)) continue;
      bool coplanar = true;
      for (const Vec3& v : b.vertices)
        coplanar = coplanar && std::abs(a.plane.signedDistance(v)) <= slack;
      if (!coplanar) continue;
      contacts[a.id].push_back(b.id);
      contacts[b.id].push_back(a.id);
    }
  return contacts;
}

}  // namespace penumbra
