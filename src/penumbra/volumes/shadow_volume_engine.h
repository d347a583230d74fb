#pragma once
// The real-time shadow engine (DESIGN.md §1, third row): shadow volumes of every object from every
// light, kept up to date incrementally while objects and lights move and while a light's sample
// point is jittered for soft shadows. The GL drawing is render/shadow_volume_renderer.h; this
// layer is CPU geometry only.
//
// Papers: McReynolds & Blythe, "Advanced Graphics Programming Techniques Using OpenGL", §11.3.2.3;
// Everitt & Kilgard 2002 (robust z-fail volumes). See object_volume.h for the construction and the
// update rules.
//
// Shape of the API: build(scene, frame), update(scene, newFrame), stats(). An incremental update
// leaves exactly the geometry a fresh build at the new frame would have, to rounding.

#include <cstdint>
#include <vector>

#include "penumbra/scene/scene.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "penumbra/volumes/light_samples.h"
#include "penumbra/volumes/object_volume.h"
#include "penumbra/volumes/occluder_mesh.h"

namespace penumbra {

struct VolumeOptions {
  // 1 / k, where k = |light base| / |light occluder| is the distance ratio of the base; 0 puts the
  // base at infinity (w = 0), which needs an infinite far plane and depth clamp when drawn.
  double baseW = 0;
};

// What one update (or build) did, counted over light x object volumes.
struct VolumeUpdateStats {
  double frame = 0;
  int volumes = 0;
  int unchanged = 0;      // neither the light nor the object moved
  int lightMoves = 0;     // light moved, silhouette kept: base translated by one constant vector
  int occluderMoves = 0;  // object moved, silhouette kept: vertices moved with it
  int linearMoves = 0;  // of occluderMoves: same translation as the frame before (simplified form)
  int rebuilds = 0;     // silhouette changed (or a fresh build): volume rebuilt
  long long silhouetteEdges = 0;
  long long capTriangles = 0;
  double seconds = 0;
};

struct VolumeStats {
  std::vector<VolumeUpdateStats> frames;  // build first, then one entry per update()
  long long jitterIncremental = 0;        // light-sample moves done by the constant-vector rule
  long long jitterRebuilds = 0;           // light-sample moves whose silhouette differed
};

// Volumes of all objects from one light's current point.
struct LightVolumes {
  PolygonId polygon = -1;             // the emitting polygon (flat scene id)
  int objectIndex = -1;               // the object it belongs to
  Polygon3 worldPolygon;              // the light polygon at the current frame
  Vec3 position;                      // the current point light (centroid, or a jittered sample)
  std::vector<ObjectVolume> objects;  // one per scene object
};

class ShadowVolumeEngine {
 public:
  explicit ShadowVolumeEngine(const VolumeOptions& options = {});

  // Fresh volumes at the live scene's current pose, each light at its polygon's area centroid.
  void build(const DynamicScene& scene);
  // Brings the volumes to the scene's new pose after `change` was applied to it, incrementally:
  // only the volumes of moved objects and moved lights change (object_volume.h's rules).
  void update(const DynamicScene& scene, const SceneChange& change);
  // The same at keyframe poses of a scene (no live scene needed: volumes use no grid or caster).
  // Precondition: the scene is valid (as loadScene returns it); update follows a build of `scene`.
  void build(const Scene& scene, double frame);
  void update(const Scene& scene, double newFrame);
  // Moves light `light`'s point to `position` (a jittered sample on the light, or back to the
  // centroid): the constant-vector rule per object, a rebuild for objects whose silhouette
  // differs. Precondition: 0 <= light < lights().size().
  void moveLight(int light, const Vec3& position);

  // Soft shadows by jittering (McReynolds & Blythe §11.3.2.3): for every light in turn, moves its
  // point to each of `samples` stratified samples on its polygon (light_samples.h, seeded with
  // seed + light index) by moveLight's constant-vector rule, calls visit(light, position,
  // samples) with the volumes of that sample in place, then puts the light back at its centroid.
  // The drawing (render/shadow_volume_renderer.h) only draws what it is handed. Precondition:
  // samples >= 1.
  template <typename Visit>
  void forEachLightSample(int samples, std::uint64_t seed, Visit&& visit) {
    for (int l = 0; l < int(lights_.size()); ++l) {
      const Polygon3 polygon = lights_[l].worldPolygon;
      const std::vector<Vec3> positions = stratifiedLightSamples(polygon, samples, seed + l);
      for (const Vec3& position : positions) {
        moveLight(l, position);
        visit(l, position, int(positions.size()));
      }
      moveLight(l, centroid(polygon));
    }
  }

  const std::vector<LightVolumes>& lights() const { return lights_; }
  const VolumeStats& stats() const { return stats_; }
  const VolumeOptions& options() const { return options_; }
  double frame() const { return frame_; }

 private:
  struct ObjectState {
    OccluderMesh mesh;
    Transform transform;
    bool hasLinearStep = false;
    Vec3 linearStep;  // the last frame's translation
  };
  struct Anchor {  // linear motion: positions at the start of the current run of equal steps
    std::vector<Vec3> nearVertices, baseVertices;
    int steps = 0;
  };

  void buildWith(const Scene& scene, const std::vector<Transform>& transforms, double frame);
  void updateTo(const Scene& scene, const std::vector<Transform>& newTransforms, double newFrame);
  int excludedPolygon(int light, int object) const;
  ObjectVolume rebuild(int light, int object) const;

  VolumeOptions options_;
  double frame_ = 0;
  std::vector<ObjectState> objects_;
  std::vector<LightVolumes> lights_;
  std::vector<std::vector<Anchor>> anchors_;  // [light][object]
  std::vector<int> lightLocalPolygon_;        // the light's polygon index within its object
  VolumeStats stats_;
};

}  // namespace penumbra
