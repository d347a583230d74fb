#pragma once
// How the front ends reach a frame (DESIGN.md §6): from the live scene's current keyframe pose,
// one frame at a time, each step applied to the shared scene and then handed to the engines'
// update(). An engine built at frame 0 and walked to K must equal one built at K (`--full`).

#include "penumbra/spatial/dynamic_scene.h"

namespace penumbra::cli {

// onChange(const SceneChange&) runs after each step is applied to `live`.
template <typename OnChange>
void walkToFrame(DynamicScene& live, int frame, OnChange&& onChange) {
  const int step = frame >= live.frame() ? 1 : -1;
  for (int f = int(live.frame()) + step; step > 0 ? f <= frame : f >= frame; f += step) {
    const SceneChange change = live.changeToFrame(f);
    live.apply(change);
    onChange(change);
  }
}

// Brings `engine` to keyframe `frame` of `live`: built at the first frame of a run, else the step
// to `frame` applied to the live scene and handed to the engine's update(). Returns how many
// objects the step moved.
template <typename Engine>
int buildOrStep(DynamicScene& live, Engine& engine, int frame, bool isFirst) {
  if (isFirst) {
    engine.build(live);
    return 0;
  }
  const SceneChange change = live.changeToFrame(frame);
  live.apply(change);
  engine.update(live, change);
  return int(change.moves.size());
}

}  // namespace penumbra::cli
