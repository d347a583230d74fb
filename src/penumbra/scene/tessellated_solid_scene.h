#pragma once
// The stress scenes for polygons of many vertices and many nearly parallel edges: a finely
// tessellated disc, or a closed cylinder (a side of N quads and two N-gon caps), floating over a
// floor under a square light, in the JSON scene format (DESIGN.md §4). Every EV event of every
// side edge and vertex crosses the floor's penumbra, so the discontinuity mesh grows about as
// N^1.6 faces; `bench/dm_many_vertices` and the tests use these to keep its cost polynomial.

#include <string>

namespace penumbra {

struct TessellatedSolidOptions {
  int sides = 1000;       // vertices of the disc, or of each cap of the cylinder (3 or more)
  bool cylinder = false;  // a closed cylinder of height 0.1 instead of a flat disc
};

// A 1 x 1 floor at y = 0 (facing up), a 0.2 x 0.2 light at y = 1 facing down, and the disc of
// radius 0.3 at y = 0.5 centred over the floor (facing down; the cylinder spans y = 0.45..0.55),
// its first vertex at angle 0.1 rad so that no side is parallel to a light edge. One frame.
std::string tessellatedSolidSceneJson(const TessellatedSolidOptions& options);

}  // namespace penumbra
