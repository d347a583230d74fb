#pragma once
// The dynamic scene (DESIGN.md §4): materials, objects (some emissive: the lights), optional
// camera, frame count. Immutable after loading; `poseAt` gives the world geometry of a frame.

#include <optional>
#include <string>
#include <vector>

#include "penumbra/scene/camera.h"
#include "penumbra/scene/material.h"
#include "penumbra/scene/scene_object.h"

namespace penumbra {

// Stable identity of an input polygon across frames: its index in the scene's flat polygon order
// (objects in file order, polygons in object order).
using PolygonId = int;

struct Scene {
  std::string sourcePath;
  std::vector<Material> materials;
  std::vector<SceneObject> objects;
  std::optional<Camera> camera;
  int frames = 1;

  int polygonCount() const;
  int dynamicObjectCount() const;
  // First flat PolygonId of each object (size objects.size() + 1).
  std::vector<PolygonId> objectPolygonOffsets() const;
};

}  // namespace penumbra
