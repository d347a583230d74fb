#pragma once
// The world geometry of one pose of the scene: every input polygon transformed, with its plane,
// material and stable id, plus each object's transform. Engines read scenes only through this
// (usually through the DynamicScene that keeps it up to date, spatial/dynamic_scene.h).

#include <vector>

#include "penumbra/geometry/edge_runs.h"
#include "penumbra/scene/scene.h"
#include "penumbra/scene/scene_change.h"

namespace penumbra {

struct WorldPolygon {
  PolygonId id = 0;  // == index in PosedScene::polygons
  int objectIndex = 0;
  int material = 0;
  Polygon3 vertices;  // world space, counter-clockwise seen from the front
  Plane plane;        // unit normal towards the front
  double area = 0;
  Box3 bounds;
  // edgeRuns(vertices): empty unless the polygon has many vertices (geometry/edge_runs.h).
  std::vector<VertexRun> edgeRuns;
  bool isLight = false;
  // The closed surface of its object it is part of (closed_surface.h; an index into
  // PosedScene::closedSurfaces), or -1. Found in object space, so the same at every pose: a
  // transform maps equal corners to equal corners, and a mirroring one reverses every polygon.
  int closedSurface = -1;
};

// A closed surface among an object's polygons (closed_surface.h): a box of a piece of furniture.
struct ClosedSurface {
  std::vector<PolygonId> polygons;  // the same at every pose
  Box3 bounds;                      // at this pose
};

struct PosedScene {
  double frame = 0;
  std::vector<WorldPolygon> polygons;
  std::vector<PolygonId> lights;    // polygons whose material emits
  std::vector<Material> materials;  // copy of the scene's, indexed by WorldPolygon::material
  // Bounds of this pose's polygons.
  Box3 bounds;
  // Frame-invariant bounds: every pose the scene can reach (reach_bounds.h), grown only when a
  // caller moves an object outside it. Every relative tolerance ("1e-9 of the scene's size") and
  // the shared grid are taken from this, never from `bounds`, so that they are the same at every
  // frame and an updated solution can equal one computed from scratch bit for bit.
  Box3 extent;
  std::vector<Transform> objectTransforms;    // object-to-world, indexed like Scene::objects
  std::vector<PolygonId> objectFirstPolygon;  // first PolygonId of each object, plus the count
  // Every closed surface (WorldPolygon::closedSurface).
  std::vector<ClosedSurface> closedSurfaces;

  const Material& materialOf(const WorldPolygon& p) const { return materials[p.material]; }
  int objectCount() const { return int(objectTransforms.size()); }
};

// The scene at a keyframe pose; extent = reachBounds(scene).
PosedScene poseAt(const Scene& scene, double frame);
// The scene with every object at the given transform (one per object), and the given extent
// (which must contain the posed polygons).
PosedScene poseWith(const Scene& scene, std::vector<Transform> transforms, const Box3& extent,
                    double frame);

// Re-poses the polygons of the moved objects (ids, materials and order unchanged) and recomputes
// `bounds`; the caller sets `extent` and `frame`. Each moved polygon is computed exactly as
// poseWith computes it, so the result equals a fresh pose bit for bit.
void applyMoves(const Scene& scene, const SceneChange& change, PosedScene& posed);

// For posed scenes assembled polygon by polygon (tests): derives the object table from the
// polygons' objectIndex (each object's polygons contiguous, in order), with identity transforms,
// and the closed surfaces, recomputes `bounds`, and sets `extent` to them.
void indexObjects(PosedScene& posed);

// The object-to-world transform of every object at a keyframe pose.
std::vector<Transform> transformsAt(const Scene& scene, double frame);

}  // namespace penumbra
