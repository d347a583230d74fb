#pragma once
// Procedural scenes for scaling benchmarks: furnished rooms of a requested polygon count in the
// JSON scene format (DESIGN.md §4), of the same kind as the bundled office-desk scenes.

#include <cstdint>
#include <string>

namespace penumbra {

struct SceneGeneratorOptions {
  int targetPolygons = 1000;
  std::uint64_t seed = 1;
  int frames = 4;
  // Boxes moving above the central desk (1 to 4): the first as described below, each other one a
  // box and a half higher, every other one travelling the other way (6 polygons each).
  int movingBoxes = 1;
};

// A closed room (floor, walls, ceiling) furnished with non-overlapping shelves of books, tables,
// desks with chairs, cabinets with drawers and stacks of boxes, lit by one 0.6 m square ceiling
// light; a 0.15 m box floats above the central desk and moves through `frames` keyframes
// (translation only). The room grows with the target and so does the detail per piece of
// furniture. The polygon count is exactly targetPolygons for targets of 54 and up; smaller ones
// give the minimal scene of 49 polygons. Deterministic for a given seed; different
// seeds give different layouts. With movingBoxes above 1, the minimal scene grows by 6 polygons per
// extra box. Every piece of furniture is a union of closed convex solids
// with outward faces, and no two objects' bounding boxes share interior. Returns the JSON text.
std::string generateSceneJson(const SceneGeneratorOptions& options);

}  // namespace penumbra
