#pragma once
// Polygons lying on one another: in one plane, their bounds overlapping. Facing each other they are
// in face-to-face contact (a box standing on the floor, a handle on a drawer, a sideboard's back
// against a wall) and each sees only the other where they overlap; facing the same way one lies on
// top. The ray caster, which ignores polygons through a ray's ends, cannot tell, so the radiosity
// solvers ask this.

#include <vector>

#include "penumbra/scene/posed_scene.h"

namespace penumbra {

// For each polygon, the polygons that may cover part of it (within 1e-9 of the scene's size of
// one plane, bounds overlapping; where a polygon is covered it neither receives nor sends light):
//  - those in face-to-face contact with it, both ways (a box standing on the floor: the box's
//    bottom and the floor cover each other), not the other side of a sheet (two polygons back to
//    back with open space on both sides, a two-sided card; told apart from solids in contact by
//    rays against the two polygons' objects);
//  - those lying on it facing the same way that come later in the scene (a rug on a floor, a
//    decal, a box's bottom on the floor with its faces turned inwards: the later lies on top),
//    except that a light lies on top of a polygon that emits nothing, whichever comes first (a
//    lamp set into the ceiling's plane). Without these both polygons of such a pair took the light
//    arriving where they overlap and both sent it on: a closed cavity over such a pair (an
//    inside-out box standing on the floor) returned more light than reached it, and its radiosity
//    grew without bound (1e5 times the room's, refinement past millions of links).
// Taken as covering each other, both sides of a two-sided card received nothing.
std::vector<std::vector<PolygonId>> coveringPolygons(const PosedScene& scene);

// Of polygons lying on one another facing the same way, the one on top at a point: from
// `polygon` (where a locator found the point), the covering polygon facing its way for which
// `holds(partner)` (the point lies on it), and so on up. The covering relation orders such
// polygons (lights over the rest, then by id), so the climb ends.
template <typename Holds>
PolygonId polygonOnTop(const PosedScene& scene, const std::vector<std::vector<PolygonId>>& covering,
                       PolygonId polygon, Holds&& holds) {
  for (bool climbed = true; climbed;) {
    climbed = false;
    for (PolygonId partner : covering[size_t(polygon)])
      if (dot(scene.polygons[size_t(partner)].plane.normal,
              scene.polygons[size_t(polygon)].plane.normal) > 0 &&
          holds(partner)) {
        polygon = partner;
        climbed = true;
        break;
      }
  }
  return polygon;
}

}  // namespace penumbra
