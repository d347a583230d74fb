#pragma once
// Planar mirrors of a frame: the polygons whose material has `mirror` set, grouped by plane and
// material, each group with the reflection through its plane.
//
// Paper: McReynolds & Blythe, "Advanced Graphics Programming Techniques Using OpenGL" (1999/2005),
// planar reflections (the scene reflected through the mirror plane, drawn only where the mirror
// is seen) and §11.3.2.3 (the reflected light's shadow volume is the original one under the same
// reflection). A group is what one stencil-masked reflection pass draws: every polygon of it
// shares the reflection and the tint.

#include <vector>

#include "penumbra/base/rgb.h"
#include "penumbra/geometry/plane.h"
#include "penumbra/geometry/transform.h"
#include "penumbra/scene/posed_scene.h"

namespace penumbra {

struct MirrorPlane {
  Plane plane;                      // the first polygon's plane: its front side shows the image
  Transform reflection;             // x -> x - 2 (n . x - d) n, its own inverse
  Rgb reflectance;                  // of the mirror material: what fraction of the image is seen
  std::vector<PolygonId> polygons;  // the mirror polygons in this plane with this material
};

// The reflection through `plane`. Postcondition: isReflection(); applying it twice is identity
// to rounding.
Transform reflectionThrough(const Plane& plane);

// True when every vertex of `polygon` lies within `tolerance` of `plane` (either orientation):
// such a polygon is its own mirror image and is never seen in that mirror.
bool liesInPlane(const WorldPolygon& polygon, const Plane& plane, double tolerance);

// The mirror groups of `scene`, in order of their first polygon. Two mirror polygons share a
// group when they have the same material and the same oriented plane to 1e-9 of the scene's size
// (1e-9 in the normal); mirrors facing opposite ways are different groups. Emitters are never
// mirrors (their radiance is their own).
std::vector<MirrorPlane> findMirrorPlanes(const PosedScene& scene);

}  // namespace penumbra
