#pragma once
// Motion as data (DESIGN.md §2): a SceneChange is one step from a pose of the scene to the next.
// It names the objects that moved (a light is an object with emitting polygons), with their old
// and new object-to-world transforms and world bounds, and nothing else. Changes come from the
// scene's keyframes (DynamicScene::changeToFrame) or from a caller (DynamicScene::changeMoving: a
// drag in the viewer, a script); engines take both through one `update(change)` and never assume
// keyframes.
//
// Identities that stay stable across every change: an object's index in Scene::objects, a
// PolygonId (flat index in the scene's polygon order), a feature (polygon, corner). A change never
// adds or removes polygons.

#include <vector>

#include "penumbra/geometry/box.h"
#include "penumbra/geometry/transform.h"

namespace penumbra {

struct ObjectMove {
  int object = -1;
  Transform before, after;  // object-to-world
  Box3 boundsBefore, boundsAfter;
  // Contains every pose between `before` and `after`: for a keyframe step, under the motion's
  // interpolation (translation and scale linear, rotation by slerp); a caller's move is a jump
  // (both ends only). What a shaft or motion volume must test.
  Box3 swept;
  bool carriesLight = false;  // some polygon of the object emits
};

struct SceneChange {
  double frameBefore = 0, frameAfter = 0;
  std::vector<ObjectMove> moves;  // by increasing object index
  // The scene's extent (PosedScene::extent) grows: a caller moved an object outside every pose the
  // scene could reach before. Frame-invariant tolerances and the grid change with it, so every
  // engine must recompute from scratch.
  bool extentGrows = false;

  bool isEmpty() const { return moves.empty() && frameBefore == frameAfter; }
  bool movesLight() const {
    for (const ObjectMove& m : moves)
      if (m.carriesLight) return true;
    return false;
  }
  const ObjectMove* moveOf(int object) const {
    for (const ObjectMove& m : moves)
      if (m.object == object) return &m;
    return nullptr;
  }
};

// Two transforms are the same pose only when bit for bit equal: an engine told nothing moved must
// be able to keep every derived value as it is.
bool isSameTransform(const Transform& a, const Transform& b);

}  // namespace penumbra
