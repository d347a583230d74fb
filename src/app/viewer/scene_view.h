#pragma once
// What the viewer shows: one live scene (DynamicScene: the scene, its current pose, the shared grid
// and ray caster) and the engines over it, kept alive across frames and moves, drawn by one of the
// engines into a radiometric image. The viewer is a thin client: every pixel comes from the same
// library calls as `penumbra render` (render_command.cpp), so a screenshot can be compared with
// the CLI's image of the same method and pose.
//
//  - raytrace:  renderRayTraced over the live grid and ray caster (exact soft shadows per pixel;
//               slow; nothing of its own to update: the live scene moves the grid and the caster)
//  - radiosity: the hierarchical radiosity mesh, radiance B / pi per vertex, MeshRenderer
//  - volumes:   the shadow-volume engine, drawn live with N jittered light samples and mirror
//               reflections (ShadowVolumeRenderer)
//
// Every pose change is a SceneChange (frame steps from the keyframes, moves from the user), applied
// to the live scene and then handed to the engines' update(), as the CLI's frame walk does.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/geometry/box.h"
#include "penumbra/radiosity/combined_solution.h"
#include "penumbra/radiosity/galerkin/galerkin_radiosity.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/render/image.h"
#include "penumbra/render/mesh_renderer.h"
#include "penumbra/render/shadow_volume_renderer.h"
#include "penumbra/scene/camera.h"
#include "penumbra/scene/scene.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "penumbra/volumes/shadow_volume_engine.h"

namespace penumbra::viewer {

enum class ViewMethod { kRaytrace, kRadiosity, kVolumes, kCombined, kGalerkin };

// "raytrace" | "radiosity" | "volumes" | "combined" | "galerkin", or nothing.
std::optional<ViewMethod> parseViewMethod(const std::string& name);
const char* methodName(ViewMethod method);

// What the last call that changed the pose (setFrame or moveObject) did, summed over the changes
// it applied: shown in the viewer's panel.
struct SceneUpdate {
  int changes = 0;                // changes applied: frames walked, or 1 for a move
  std::vector<int> movedObjects;  // objects some change moved, by increasing index
  bool extentGrew = false;        // a move left the scene's reach: grid and caster rebuilt
  ViewMethod engine = ViewMethod::kVolumes;  // the engine shown while updating
  double engineSeconds = 0;                  // the shown engine's update() calls
  // Radiosity (or the combined solution) shown but not updated (it was not solved yet, or
  // several frames were walked): the next image solves it from scratch, which is what
  // radiosity's update() does for now anyway.
  bool radiositySolvesAfresh = false;
  double gridSeconds = 0;     // DynamicScene::lastGridSeconds over the changes
  double raySeconds = 0;      // DynamicScene::lastRaySeconds over the changes
  VolumeUpdateStats volumes;  // the volumes' counts (always kept up to date), summed
};

// A point of the scene under the cursor.
struct PickHit {
  int object = -1;  // index in Scene::objects (a light is an object with emitting polygons)
  PolygonId polygon = -1;
  Vec3 point;
};

class SceneView {
 public:
  // The scene at frame 0 with its volumes built there (the CLI's path to any frame); radiosity
  // is solved with `radiosity` when first shown. Precondition: a GL context is current and stays
  // current while this view is used.
  SceneView(const Scene& scene, ViewMethod method, const RadiosityOptions& radiosity);
  ~SceneView();

  const DynamicScene& live() const { return live_; }
  int frame() const { return int(live_.frame()); }
  ViewMethod method() const { return method_; }
  int lightSamples() const { return lightSamples_; }

  // Walks the live scene one keyframe step at a time to `frame` (either way), updating the engines
  // after each step; objects a caller moved go back to their keyframe pose. No-op at the current
  // frame. Precondition: 0 <= frame < scene().frames.
  void setFrame(int frame);
  // A caller's move (a drag, a scripted drag): the object (or light) to the object-to-world
  // transform `transform`, applied to the live scene and handed to the engines' update().
  // Preconditions: 0 <= object < object count; transform invertible.
  void moveObject(int object, const Transform& transform);
  void setMethod(ViewMethod method) { method_ = method; }
  // Precondition: n >= 1.
  void setLightSamples(int n) { lightSamples_ = n; }
  void setThreads(int threads) { threads_ = threads; }

  // The object under image point (x, y) (pixel units from the top-left of a width x height image
  // of `camera`), by the live ray caster; nothing where the ray leaves the scene.
  std::optional<PickHit> pick(const Camera& camera, int width, int height, double x,
                              double y) const;
  // World bounds of an object at its current pose.
  Box3 boundsOf(int object) const;

  // The radiance image of the current pose. Throws RenderError on GL failures.
  Image render(const Camera& camera, int width, int height);
  // What the engine did for the last render, one line.
  const std::string& status() const { return status_; }
  const SceneUpdate& lastUpdate() const { return lastUpdate_; }

 private:
  // Applies one change to the live scene and the engines; adds what it did to lastUpdate_. With
  // updateRadiosity false a shown radiosity solution is not updated but solved afresh for the
  // next image (a walk of several frames: one solve instead of one per step).
  void applyChange(const SceneChange& change, bool updateRadiosity);
  // The combined solution's display mesh, as radiances.
  ColoredMesh combinedMesh() const;

  DynamicScene live_;
  ViewMethod method_;
  int lightSamples_ = ShadowVolumeRenderOptions{}.lightSamples;
  int threads_ = 0;
  // Volumes are cheap to update and follow every change, so their state is always the CLI's
  // (built at frame 0, then updated change by change).
  ShadowVolumeEngine volumes_;
  std::unique_ptr<ShadowVolumeRenderer> volumeRenderer_;
  // Radiosity is solved when first shown, updated while shown, and re-solved (build) when shown
  // again after changes it missed: its update() recomputes everything for now, so following
  // changes while hidden would cost a solve each for nothing.
  RadiosityOptions radiosityOptions_;
  std::unique_ptr<RadiositySolver> radiosity_;
  bool radiosityIsCurrent_ = false;
  std::optional<ColoredMesh> radiosityMesh_;  // of radiosity_'s solution
  std::unique_ptr<MeshRenderer> meshRenderer_;
  // The combined solution (exact direct light, radiosity's indirect light) follows the same
  // rule: solved when shown, updated while shown, solved afresh after changes it missed. Drawn
  // as `penumbra render --method combined` draws it (back sides unlit).
  std::unique_ptr<CombinedSolution> combined_;
  bool combinedIsCurrent_ = false;
  std::optional<ColoredMesh> combinedMesh_;
  std::unique_ptr<MeshRenderer> combinedRenderer_;
  // The Galerkin core: solved when first shown, then its line-space update at every change while
  // shown (every step of a walk: each costs a fraction of a solve), solved afresh after changes
  // it missed.
  std::unique_ptr<GalerkinRadiosity> galerkin_;
  bool galerkinIsCurrent_ = false;
  std::optional<ColoredMesh> galerkinMesh_;
  SceneUpdate lastUpdate_;
  std::string status_;
};

}  // namespace penumbra::viewer
