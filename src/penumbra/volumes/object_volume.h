#pragma once
// The shadow volume one object casts from a point light, and its incremental updates.
//
// Papers: McReynolds & Blythe, "Advanced Graphics Programming Techniques Using OpenGL" (1999/2005),
// §11.3.2.3 (shadow volumes; incremental update when the light or an occluder moves; reflected
// volumes; jittered lights); Everitt & Kilgard, "Practical and Robust Stenciled Shadow Volumes for
// Hardware-Accelerated Rendering" (2002) (closed volumes with near and far caps for z-fail, base
// extruded towards infinity).
//
// Construction. Each polygon of the object that casts (see below) is a cap oriented towards the
// light L. Every near vertex v (a vertex of the occluder) has a base vertex on the ray from L
// through v at the fixed distance ratio k = |L b| / |L v| (similar triangles: b = L + k (v - L)).
// Base vertices are stored homogeneously as b / k = (v - L + L / k, 1 / k), so k = infinity (the
// default, Everitt & Kilgard's w = 0 extrusion) and finite k share one representation and one
// set of update rules, and the far cap lies at infinity with an infinite far plane.
//
// Which polygons cast. Polygons are opaque from both sides (DESIGN.md §4). On a closed,
// consistently oriented mesh the polygons facing the light cover the whole shadow, so only they are
// caps and the silhouette is the set of edges between a facing and a non-facing polygon. On an open
// mesh every polygon casts, each oriented towards the light; the side quad of an edge is dropped
// only where the neighbour's oriented cap runs through the edge the other way (the two quads would
// cancel exactly), so the boundary of an open surface and its folds are silhouettes too. Either
// way the stencil count is a sum of closed per-polygon volumes: > 0 exactly where shadowed.
//
// Incremental updates with an unchanged silhouette (the facing signature is the same):
//  - light moves by d: near vertices stay, every base vertex moves by the constant (1 - k) d (in
//  the
//    stored scaling: -(1 - 1/k) d). A jitter of the light sample is such a translation.
//  - occluder moves by a translation t: near vertices move by t, base vertices by k t (stored: t).
//  - occluder moves by any rigid/affine delta D: near vertices v' = D v, base from similar
//    triangles b' = L + k (v' - L).
// A changed signature means a changed silhouette: the volume is rebuilt.

#include <array>
#include <vector>

#include "penumbra/geometry/transform.h"
#include "penumbra/volumes/occluder_mesh.h"

namespace penumbra {

struct ObjectVolume {
  std::vector<Vec3> nearVertices;  // world positions of the occluder's welded vertices
  std::vector<Vec3> baseVertices;  // b / k = v - L + L w, with w = 1 / k (see above)
  double baseW = 0;                // 1 / k; 0: base at infinity
  // Near cap triangles oriented outward (counter-clockwise seen from the light); the far cap is
  // the same triangles on the base vertices in reverse order.
  std::vector<std::array<int, 3>> capTriangles;
  // Silhouette edges (a, b): side quad (b, a, base a, base b), outward.
  std::vector<std::array<int, 2>> silhouetteEdges;
  std::vector<signed char> facing;  // per polygon: +1 facing the light, -1 away, 0 excluded/edge-on

  bool isEmpty() const { return capTriangles.empty(); }
};

// Facing signature of every polygon of `mesh` with world vertices `nearVertices` seen from
// `light`; `excludedPolygon` (the light's own polygon, or -1) gets 0.
std::vector<signed char> facingSignature(const OccluderMesh& mesh,
                                         const std::vector<Vec3>& nearVertices, const Vec3& light,
                                         int excludedPolygon);

// A fresh volume. Precondition: nearVertices.size() == mesh.vertices.size(); baseW >= 0.
ObjectVolume buildObjectVolume(const OccluderMesh& mesh, std::vector<Vec3> nearVertices,
                               const Vec3& light, double baseW, int excludedPolygon);

// The base vertex of near vertex v for a light at `light` (similar triangles).
inline Vec3 baseVertex(const Vec3& v, const Vec3& light, double baseW) {
  return v - light + light * baseW;
}

// The light moved from `oldLight` by d with the silhouette unchanged: every base vertex moves by
// the same vector. Precondition: the facing signature at the new position equals volume.facing.
void translateLight(ObjectVolume& volume, const Vec3& d);

// The occluder moved by `delta` (new = delta * old) with the silhouette unchanged.
// Translations use the constant-vector rule; other transforms the similar-triangles rule.
void moveOccluder(ObjectVolume& volume, const Transform& delta, const Vec3& light);

// The volume under a planar reflection (or any affine transform with negative determinant): the
// reflected light's volume, with winding reversed so that faces stay outward.
ObjectVolume reflectedVolume(const ObjectVolume& volume, const Transform& reflection);

}  // namespace penumbra
