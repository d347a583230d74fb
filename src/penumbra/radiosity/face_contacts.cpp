#include "penumbra/radiosity/face_contacts.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

// Calls pair(a, b, facing) for each pair of polygons in one plane with overlapping bounds, facing
// each other or the same way, a before b. Planes are compared in a canonical orientation (first
// non-zero normal component positive), sorted by offset, so only polygons with nearly equal
// offsets are compared.
template <typename Pair>
void forEachCoplanarPair(const PosedScene& scene, Pair&& pair) {
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
      const WorldPolygon* a = &scene.polygons[order[i].second];
      const WorldPolygon* b = &scene.polygons[order[j].second];
      const double cosine = dot(a->plane.normal, b->plane.normal);
      const bool facing = cosine <= -1 + 1e-9;
      if (!facing && cosine < 1 - 1e-9) continue;
      if (!a->bounds.expanded(slack).overlaps(b->bounds)) continue;
      bool coplanar = true;
      for (const Vec3& v : b->vertices)
        coplanar = coplanar && std::abs(a->plane.signedDistance(v)) <= slack;
      if (!coplanar) continue;
      if (b->id < a->id) std::swap(a, b);
      pair(*a, *b, facing);
    }
}

void sortEach(std::vector<std::vector<PolygonId>>& lists) {
  for (std::vector<PolygonId>& list : lists) std::sort(list.begin(), list.end());
}

}  // namespace

std::vector<std::vector<PolygonId>> faceContacts(const PosedScene& scene) {
  std::vector<std::vector<PolygonId>> contacts(scene.polygons.size());
  forEachCoplanarPair(scene, [&](const WorldPolygon& a, const WorldPolygon& b, bool facing) {
    if (!facing) return;
    contacts[a.id].push_back(b.id);
    contacts[b.id].push_back(a.id);
  });
  return contacts;
}

std::vector<std::vector<PolygonId>> coveringPolygons(const PosedScene& scene) {
  std::vector<std::vector<PolygonId>> covering(scene.polygons.size());
  forEachCoplanarPair(scene, [&](const WorldPolygon& a, const WorldPolygon& b, bool facing) {
    // Back to back in one object: the two sides of a sheet (a card, a leaf), both exposed. A
    // closed object has no such pair; polygons of two objects facing each other are in contact.
    if (facing && a.objectIndex == b.objectIndex) return;
    if (facing) {
      covering[a.id].push_back(b.id);
      covering[b.id].push_back(a.id);
    } else if (a.isLight && !b.isLight) {
      covering[b.id].push_back(a.id);  // a lamp set into a ceiling: the lamp is what shows
    } else {
      covering[a.id].push_back(b.id);
    }
  });
  sortEach(covering);
  return covering;
}

}  // namespace penumbra
