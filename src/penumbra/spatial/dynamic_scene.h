#pragma once
// The live scene every engine shares (DESIGN.md §2, "motion is data"): the loaded Scene, its
// current pose (PosedScene), and the spatial structures over it — one regular grid and one ray
// caster, not one per engine. A change is made first (changeToFrame: the keyframes; changeMoving:
// any rigid transform a caller gives), then committed with apply(), which re-poses only the moved
// objects and moves them in the grid and the ray caster (Embree's commit model: per-object
// modification counters say what was touched). Engines are then told the same change through
// their update(scene, change).
//
// Invariant: after any sequence of applied changes, posed(), grid() and rays() equal those of a
// DynamicScene constructed at the resulting pose with the same extent (the cell lists bit for bit,
// the caster hit for hit), which is what lets an updated engine equal one built from scratch.
//
// The extent covers every pose of the scene's keyframes. A caller's move outside it grows the
// extent (by a margin, so that a drag does not re-grid at every step): the grid and the caster are
// then rebuilt over the new extent and the change says so (SceneChange::extentGrows).

#include <memory>
#include <vector>

#include "penumbra/scene/posed_scene.h"
#include "penumbra/scene/scene.h"
#include "penumbra/scene/scene_change.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

class DynamicScene {
 public:
  // The scene at keyframe pose `frame` (it keeps its own copy of `scene`).
  DynamicScene(const Scene& scene, double frame);
  // The scene with every object at `transforms` and the given extent (grown to hold the pose):
  // the from-scratch twin of a DynamicScene that reached this pose by changes.
  DynamicScene(const Scene& scene, std::vector<Transform> transforms, const Box3& extent,
               double frame);
  // A static scene from a posed one (tests, tools): one object per objectIndex, in world
  // coordinates with identity transforms.
  explicit DynamicScene(const PosedScene& posed);
  ~DynamicScene();
  DynamicScene(const DynamicScene&) = delete;
  DynamicScene& operator=(const DynamicScene&) = delete;

  const Scene& scene() const { return scene_; }
  const PosedScene& posed() const { return posed_; }
  const UniformGrid& grid() const { return *grid_; }
  const RayCaster& rays() const { return *rays_; }
  double frame() const { return posed_.frame; }
  const Box3& extent() const { return posed_.extent; }
  const Transform& transformOf(int object) const { return posed_.objectTransforms[object]; }
  // How many applied changes moved the object (Embree's per-geometry modification counter).
  long long modificationCount(int object) const { return modifications_[object]; }

  // The step to keyframe pose `frame`: every object whose transform there differs from its current
  // one (an object a caller moved goes back to its keyframe pose). Does not apply it.
  SceneChange changeToFrame(double frame) const;
  // A caller's move of one object (or light) to the object-to-world transform `transform`; the
  // frame stays. Precondition: 0 <= object < objectCount, transform invertible.
  SceneChange changeMoving(int object, const Transform& transform) const;
  // Applies a change made by this scene at its current pose: re-poses the moved objects and moves
  // them in the grid and the ray caster (or rebuilds both over a grown extent).
  void apply(const SceneChange& change);

  // Seconds spent by the last apply() in the grid and in the ray caster.
  double lastGridSeconds() const { return lastGridSeconds_; }
  double lastRaySeconds() const { return lastRaySeconds_; }

 private:
  ObjectMove makeMove(int object, const Transform& after) const;
  void buildStructures();

  Scene scene_;
  PosedScene posed_;
  std::unique_ptr<UniformGrid> grid_;
  std::unique_ptr<RayCaster> rays_;
  std::vector<long long> modifications_;
  double lastGridSeconds_ = 0, lastRaySeconds_ = 0;
};

}  // namespace penumbra
