#pragma once
// Closedness of objects: an object is closed when its polygons bound a volume, i.e. the boundary of
// its polygon chain vanishes — along every line, the edges traversed one way cover exactly the
// same points as the edges traversed the other way. T-junctions (one long edge matched by several
// short ones) are fine. A closed scene guarantees that every ray from inside hits something, which
// the discontinuity-mesh engine relies on.

#include <string>
#include <vector>

#include "penumbra/scene/posed_scene.h"

namespace penumbra {

struct ObjectClosedness {
  int objectIndex = 0;
  bool isClosed = true;
  double openEdgeLength = 0;  // total length of edges not matched by opposite edges
  int openEdgeCount = 0;      // edges with an unmatched part
};

struct ClosednessReport {
  std::vector<ObjectClosedness> objects;  // each object on its own
  // The scene's polygons together bound volumes: either all of them, or all but the lights
  // (emitting panels are open surfaces; a room shell may be split over several objects).
  bool isSceneClosed = true;
  int sceneOpenEdgeCount = 0;      // of the non-emitting polygons, when the scene is open
  double sceneOpenEdgeLength = 0;  // likewise
};

ClosednessReport checkClosedness(const Scene& scene, const PosedScene& posed);

}  // namespace penumbra
