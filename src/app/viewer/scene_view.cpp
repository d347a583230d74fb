#include "scene_view.h"

#include <utility>

#include "penumbra/base/check.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/render/radiance_mesh.h"
#include "penumbra/render/ray_traced_image.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra::viewer {

std::optional<ViewMethod> parseViewMethod(const std::string& name) {
  if (name == "raytrace") return ViewMethod::kRaytrace;
  if (name == "radiosity") return ViewMethod::kRadiosity;
  if (name == "volumes") return ViewMethod::kVolumes;
  return std::nullopt;
}

const char* methodName(ViewMethod method) {
  switch (method) {
    case ViewMethod::kRaytrace:
      return "raytrace";
    case ViewMethod::kRadiosity:
      return "radiosity";
    case ViewMethod::kVolumes:
      return "volumes";
  }
  return "?";
}

struct SceneView::RayTracing {
  explicit RayTracing(const PosedScene& posed)
      : grid(posed), reference(posed, &grid), rays(posed) {}
  UniformGrid grid;
  ExactReference reference;
  RayCaster rays;
};

SceneView::SceneView(Scene scene, ViewMethod method)
    : scene_(std::move(scene)), method_(method), posed_(poseAt(scene_, 0)) {}

SceneView::~SceneView() = default;

void SceneView::setFrame(int frame) {
  CHECK(frame >= 0 && frame < scene_.frames);
  if (frame == frame_) return;
  frame_ = frame;
  posed_ = poseAt(scene_, frame);
  radiosityMesh_.reset();
  rayTracing_.reset();
}

Image SceneView::render(const Camera& camera, int width, int height) {
  switch (method_) {
    case ViewMethod::kVolumes: {
      if (volumesFrame_ < 0 || volumesFrame_ > frame_) {
        volumes_.build(scene_, 0);
        volumesFrame_ = 0;
      }
      while (volumesFrame_ < frame_) volumes_.update(scene_, ++volumesFrame_);
      if (!volumeRenderer_) volumeRenderer_ = std::make_unique<ShadowVolumeRenderer>();
      ShadowVolumeRenderOptions options;
      options.lightSamples = lightSamples_;
      options.mirrors = true;  // as `penumbra render --method volumes` draws its PNG
      Image image = volumeRenderer_->render(posed_, volumes_, camera, width, height, options);
      const VolumeUpdateStats& s = volumes_.stats().frames.back();
      status_ = std::to_string(s.volumes) + " volumes, " + std::to_string(s.silhouetteEdges) +
                " silhouette edges; last update: " + std::to_string(s.rebuilds) + " rebuilt, " +
                std::to_string(s.occluderMoves) + " occluder moves, " +
                std::to_string(s.lightMoves) + " light moves";
      return image;
    }
    case ViewMethod::kRadiosity: {
      if (!radiosityMesh_) {
        RadiosityOptions radiosityOptions;
        radiosityOptions.tolerance = tolerance_;
        RadiositySolver solver(radiosityOptions);
        solver.build(posed_);
        radiosityMesh_ = radianceMesh(solver.mesh());
      }
      if (!meshRenderer_) meshRenderer_ = std::make_unique<MeshRenderer>();
      status_ = std::to_string(radiosityMesh_->indices.size() / 3) + " mesh triangles";
      return meshRenderer_->render(*radiosityMesh_, camera, width, height);
    }
    case ViewMethod::kRaytrace: {
      if (!rayTracing_) rayTracing_ = std::make_unique<RayTracing>(posed_);
      RayTraceOptions options;
      options.width = width;
      options.height = height;
      options.threads = threads_;
      status_ = "exact reference per pixel";
      return renderRayTraced(posed_, camera, rayTracing_->rays, rayTracing_->reference, options)
          .radiance;
    }
  }
  return {};
}

}  // namespace penumbra::viewer
