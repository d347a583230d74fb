#pragma once
// The world geometry of one frame: every input polygon transformed, with its plane, material and
// stable id. Engines read scenes only through this.

#include <vector>

#include "penumbra/scene/scene.h"

namespace penumbra {

struct WorldPolygon {
  PolygonId id = 0;  // == index in PosedScene::polygons
  int objectIndex = 0;
  int material = 0;
  Polygon3 vertices;  // world space, counter-clockwise seen from the front
  Plane plane;        // unit normal towards the front
  double area = 0;
  Box3 bounds;
  bool isLight = false;
};

struct PosedScene {
  double frame = 0;
  std::vector<WorldPolygon> polygons;
  std::vector<PolygonId> lights;    // polygons whose material emits
  std::vector<Material> materials;  // copy of the scene's, indexed by WorldPolygon::material
  Box3 bounds;

  const Material& materialOf(const WorldPolygon& p) const { return materials[p.material]; }
};

PosedScene poseAt(const Scene& scene, double frame);

}  // namespace penumbra
