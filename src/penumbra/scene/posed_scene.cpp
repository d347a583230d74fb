#include "penumbra/scene/posed_scene.h"

#include <algorithm>

#include "penumbra/base/check.h"
#include "penumbra/scene/closed_surface.h"
#include "penumbra/scene/reach_bounds.h"

namespace penumbra {

namespace {

void posePolygon(const SceneObject& object, int k, const Transform& transform, WorldPolygon& wp) {
  wp.vertices.clear();
  wp.vertices.reserve(object.polygons[k].size());
  for (const Vec3& p : object.polygons[k]) wp.vertices.push_back(transform.applyToPoint(p));
  // A mirroring transform flips winding; restore counter-clockwise-from-the-front.
  if (transform.isReflection()) std::reverse(wp.vertices.begin(), wp.vertices.end());
  wp.plane = supportingPlane(wp.vertices);
  wp.area = area(wp.vertices);
  wp.bounds = boundingBox(wp.vertices);
  wp.edgeRuns = edgeRuns(wp.vertices);
}

void recomputeBounds(PosedScene& posed) {
  posed.bounds = {};
  for (const WorldPolygon& wp : posed.polygons) posed.bounds.extend(wp.bounds);
  for (ClosedSurface& surface : posed.closedSurfaces) {
    surface.bounds = {};
    for (PolygonId id : surface.polygons) surface.bounds.extend(posed.polygons[size_t(id)].bounds);
  }
}

// Numbers the closed surfaces among one object's polygons (`rings`, those of polygons[first...])
// after those found so far.
void addClosedSurfaces(const std::vector<const Polygon3*>& rings, PolygonId first,
                       PosedScene& posed) {
  const int before = int(posed.closedSurfaces.size());
  const std::vector<int> surfaces = closedSurfaces(rings);
  for (size_t k = 0; k < surfaces.size(); ++k) {
    if (surfaces[k] < 0) continue;
    const int surface = before + surfaces[k];
    if (int(posed.closedSurfaces.size()) <= surface)
      posed.closedSurfaces.resize(size_t(surface) + 1);
    posed.closedSurfaces[size_t(surface)].polygons.push_back(first + PolygonId(k));
    posed.polygons[size_t(first) + k].closedSurface = surface;
  }
}

}  // namespace

void indexObjects(PosedScene& posed) {
  posed.objectFirstPolygon.clear();
  posed.objectTransforms.clear();
  for (const WorldPolygon& wp : posed.polygons) {
    CHECK_GE(wp.objectIndex, posed.objectCount() - 1);
    while (posed.objectCount() <= wp.objectIndex) {
      posed.objectFirstPolygon.push_back(wp.id);
      posed.objectTransforms.push_back(Transform::identity());
    }
  }
  posed.objectFirstPolygon.push_back(PolygonId(posed.polygons.size()));
  // Identity transforms: the posed corners are the object-space ones.
  posed.closedSurfaces.clear();
  for (int object = 0; object < posed.objectCount(); ++object) {
    std::vector<const Polygon3*> rings;
    const PolygonId first = posed.objectFirstPolygon[size_t(object)];
    for (PolygonId id = first; id < posed.objectFirstPolygon[size_t(object) + 1]; ++id)
      rings.push_back(&posed.polygons[size_t(id)].vertices);
    addClosedSurfaces(rings, first, posed);
  }
  recomputeBounds(posed);
  posed.extent = posed.bounds;
}

std::vector<Transform> transformsAt(const Scene& scene, double frame) {
  std::vector<Transform> transforms;
  transforms.reserve(scene.objects.size());
  for (const SceneObject& object : scene.objects) transforms.push_back(object.transformAt(frame));
  return transforms;
}

PosedScene poseAt(const Scene& scene, double frame) {
  return poseWith(scene, transformsAt(scene, frame), reachBounds(scene), frame);
}

PosedScene poseWith(const Scene& scene, std::vector<Transform> transforms, const Box3& extent,
                    double frame) {
  CHECK_EQ(transforms.size(), scene.objects.size());
  PosedScene posed;
  posed.frame = frame;
  posed.materials = scene.materials;
  posed.polygons.reserve(scene.polygonCount());
  posed.objectTransforms = std::move(transforms);
  for (int objectIndex = 0; objectIndex < int(scene.objects.size()); ++objectIndex) {
    const SceneObject& object = scene.objects[objectIndex];
    posed.objectFirstPolygon.push_back(PolygonId(posed.polygons.size()));
    for (int k = 0; k < int(object.polygons.size()); ++k) {
      WorldPolygon wp;
      wp.id = PolygonId(posed.polygons.size());
      wp.objectIndex = objectIndex;
      wp.material = object.polygonMaterial[k];
      posePolygon(object, k, posed.objectTransforms[objectIndex], wp);
      wp.isLight = scene.materials[wp.material].isEmitter();
      if (wp.isLight) posed.lights.push_back(wp.id);
      posed.polygons.push_back(std::move(wp));
    }
    std::vector<const Polygon3*> rings;
    for (const Polygon3& polygon : object.polygons) rings.push_back(&polygon);
    addClosedSurfaces(rings, posed.objectFirstPolygon.back(), posed);
  }
  posed.objectFirstPolygon.push_back(PolygonId(posed.polygons.size()));
  recomputeBounds(posed);
  posed.extent = extent;
  posed.extent.extend(posed.bounds);
  return posed;
}

void applyMoves(const Scene& scene, const SceneChange& change, PosedScene& posed) {
  for (const ObjectMove& move : change.moves) {
    CHECK(move.object >= 0 && move.object < posed.objectCount());
    const SceneObject& object = scene.objects[move.object];
    posed.objectTransforms[move.object] = move.after;
    const PolygonId first = posed.objectFirstPolygon[move.object];
    for (int k = 0; k < int(object.polygons.size()); ++k)
      posePolygon(object, k, move.after, posed.polygons[first + k]);
  }
  recomputeBounds(posed);
}

}  // namespace penumbra
