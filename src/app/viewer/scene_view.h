#pragma once
// What the viewer shows: one scene, one frame of its motion, drawn by one of the library's
// engines into a radiometric image. The viewer is a thin client: every pixel comes from the same
// library calls as `penumbra render` (render_command.cpp), so a screenshot can be compared with
// the CLI's image of the same method and frame.
//
//  - raytrace:  renderRayTraced (exact soft shadows per pixel; slow, computed once per view)
//  - radiosity: the hierarchical radiosity mesh, radiance B / pi per vertex, MeshRenderer
//  - volumes:   the shadow-volume engine, updated incrementally frame by frame, drawn live with
//               N jittered light samples and mirror reflections (ShadowVolumeRenderer)

#include <memory>
#include <optional>
#include <string>

#include "penumbra/render/image.h"
#include "penumbra/render/mesh_renderer.h"
#include "penumbra/render/shadow_volume_renderer.h"
#include "penumbra/scene/camera.h"
#include "penumbra/scene/posed_scene.h"
#include "penumbra/scene/scene.h"
#include "penumbra/volumes/shadow_volume_engine.h"

namespace penumbra::viewer {

enum class ViewMethod { kRaytrace, kRadiosity, kVolumes };

// "raytrace" | "radiosity" | "volumes", or nothing.
std::optional<ViewMethod> parseViewMethod(const std::string& name);
const char* methodName(ViewMethod method);

class SceneView {
 public:
  // Precondition: a GL context is current and stays current while this view is used.
  SceneView(Scene scene, ViewMethod method);
  ~SceneView();

  const Scene& scene() const { return scene_; }
  const PosedScene& posed() const { return posed_; }
  int frame() const { return frame_; }
  ViewMethod method() const { return method_; }
  int lightSamples() const { return lightSamples_; }

  // Precondition: 0 <= frame < scene().frames. The volumes follow the CLI's path: built at frame
  // 0 and updated incrementally one frame at a time (going back rebuilds from frame 0).
  void setFrame(int frame);
  void setMethod(ViewMethod method) { method_ = method; }
  // Precondition: n >= 1.
  void setLightSamples(int n) { lightSamples_ = n; }
  void setRadiosityTolerance(double tolerance) { tolerance_ = tolerance; }
  void setThreads(int threads) { threads_ = threads; }

  // The radiance image of the current frame. Throws RenderError on GL failures.
  Image render(const Camera& camera, int width, int height);
  // What the engine did for the last render, one line.
  const std::string& status() const { return status_; }

 private:
  struct RayTracing;  // grid, exact reference, ray caster of the current frame

  Scene scene_;
  ViewMethod method_;
  int frame_ = 0;
  int lightSamples_ = 1;
  double tolerance_ = 1e-3;
  int threads_ = 0;
  PosedScene posed_;
  ShadowVolumeEngine volumes_;
  int volumesFrame_ = -1;  // the frame the volumes are at; -1: not built
  std::unique_ptr<ShadowVolumeRenderer> volumeRenderer_;
  std::unique_ptr<MeshRenderer> meshRenderer_;
  std::optional<ColoredMesh> radiosityMesh_;  // of the current frame
  std::unique_ptr<RayTracing> rayTracing_;    // of the current frame
  std::string status_;
};

}  // namespace penumbra::viewer
