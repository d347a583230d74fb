#include "scene_view.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <limits>

#include "camera_ray.h"
#include "penumbra/base/check.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/render/radiance_mesh.h"
#include "penumbra/render/ray_traced_image.h"
#include "penumbra/scene/reach_bounds.h"

namespace penumbra::viewer {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Adds one update's counts to those of the earlier changes of the same call; the sizes (volumes,
// edges, triangles) are the latest.
void accumulate(VolumeUpdateStats& sum, const VolumeUpdateStats& step) {
  sum.frame = step.frame;
  sum.volumes = step.volumes;
  sum.silhouetteEdges = step.silhouetteEdges;
  sum.capTriangles = step.capTriangles;
  sum.unchanged += step.unchanged;
  sum.lightMoves += step.lightMoves;
  sum.occluderMoves += step.occluderMoves;
  sum.linearMoves += step.linearMoves;
  sum.rebuilds += step.rebuilds;
  sum.seconds += step.seconds;
}

}  // namespace

std::optional<ViewMethod> parseViewMethod(const std::string& name) {
  if (name == "raytrace") return ViewMethod::kRaytrace;
  if (name == "radiosity") return ViewMethod::kRadiosity;
  if (name == "volumes") return ViewMethod::kVolumes;
  if (name == "combined") return ViewMethod::kCombined;
  if (name == "galerkin") return ViewMethod::kGalerkin;
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
    case ViewMethod::kCombined:
      return "combined";
    case ViewMethod::kGalerkin:
      return "galerkin";
  }
  return "?";
}

SceneView::SceneView(const Scene& scene, ViewMethod method, const RadiosityOptions& radiosity)
    : live_(scene, 0), method_(method), radiosityOptions_(radiosity) {
  radiosityOptions_.threads = 0;  // every core: the solution does not depend on it
  volumes_.build(live_);
}

SceneView::~SceneView() = default;

void SceneView::setFrame(int frame) {
  CHECK(frame >= 0 && frame < live_.scene().frames);
  const int current = this->frame();
  if (frame == current) return;
  lastUpdate_ = SceneUpdate{};
  lastUpdate_.engine = method_;
  // One solve at the end instead of one per step: the radiosity update recomputes anyway.
  const bool updateRadiosity = std::abs(frame - current) == 1;
  const int step = frame > current ? 1 : -1;
  for (int f = current + step; f != frame + step; f += step)
    applyChange(live_.changeToFrame(f), updateRadiosity);
}

void SceneView::moveObject(int object, const Transform& transform) {
  lastUpdate_ = SceneUpdate{};
  lastUpdate_.engine = method_;
  applyChange(live_.changeMoving(object, transform), /*updateRadiosity=*/true);
}

void SceneView::applyChange(const SceneChange& change, bool updateRadiosity) {
  live_.apply(change);
  SceneUpdate& u = lastUpdate_;
  ++u.changes;
  u.extentGrew = u.extentGrew || change.extentGrows;
  u.gridSeconds += live_.lastGridSeconds();
  u.raySeconds += live_.lastRaySeconds();
  for (const ObjectMove& move : change.moves)
    if (std::find(u.movedObjects.begin(), u.movedObjects.end(), move.object) ==
        u.movedObjects.end())
      u.movedObjects.push_back(move.object);
  std::sort(u.movedObjects.begin(), u.movedObjects.end());

  auto start = std::chrono::steady_clock::now();
  volumes_.update(live_, change);
  const double volumeSeconds = secondsSince(start);
  accumulate(u.volumes, volumes_.stats().frames.back());
  if (method_ == ViewMethod::kVolumes) u.engineSeconds += volumeSeconds;

  if (method_ == ViewMethod::kRadiosity && radiosityIsCurrent_ && updateRadiosity) {
    start = std::chrono::steady_clock::now();
    radiosity_->update(live_, change);
    radiosityMesh_ = radianceMesh(radiosity_->mesh());
    u.engineSeconds += secondsSince(start);
  } else {
    radiosityIsCurrent_ = false;
    u.radiositySolvesAfresh = method_ == ViewMethod::kRadiosity;
  }
  if (method_ == ViewMethod::kGalerkin && galerkinIsCurrent_) {
    start = std::chrono::steady_clock::now();
    galerkin_->update(live_, change);
    galerkinMesh_ = radianceMesh(galerkin_->leafMesh());
    u.engineSeconds += secondsSince(start);
  } else {
    galerkinIsCurrent_ = false;
    u.radiositySolvesAfresh = u.radiositySolvesAfresh || method_ == ViewMethod::kGalerkin;
  }
  if (method_ == ViewMethod::kCombined && combinedIsCurrent_ && updateRadiosity) {
    start = std::chrono::steady_clock::now();
    combined_->update(live_, change);
    combinedMesh_ = combinedMesh();
    u.engineSeconds += secondsSince(start);
  } else {
    combinedIsCurrent_ = false;
    u.radiositySolvesAfresh = u.radiositySolvesAfresh || method_ == ViewMethod::kCombined;
  }
}

ColoredMesh SceneView::combinedMesh() const {
  // Corners about 1/100 of the scene apart, as `penumbra render --method combined` makes them.
  return radianceMesh(combined_->displayMesh(live_.posed().extent.diagonalLength() / 100),
                      live_.posed());
}

std::optional<PickHit> SceneView::pick(const Camera& camera, int width, int height, double x,
                                       double y) const {
  const Vec3 direction = cameraRayDirection(camera, width, height, x, y);
  const std::optional<RayHit> hit =
      live_.rays().intersect(camera.eye, direction, 0, std::numeric_limits<double>::infinity());
  if (!hit) return std::nullopt;
  return PickHit{live_.posed().polygons[hit->polygon].objectIndex, hit->polygon, hit->point};
}

Box3 SceneView::boundsOf(int object) const {
  return transformedBounds(live_.scene().objects[object].polygons, live_.transformOf(object));
}

Image SceneView::render(const Camera& camera, int width, int height) {
  switch (method_) {
    case ViewMethod::kVolumes: {
      if (!volumeRenderer_) volumeRenderer_ = std::make_unique<ShadowVolumeRenderer>();
      ShadowVolumeRenderOptions options;
      options.lightSamples = lightSamples_;
      options.mirrors = true;  // as `penumbra render --method volumes` draws its PNG
      Image image =
          volumeRenderer_->render(live_.posed(), volumes_, camera, width, height, options);
      const VolumeUpdateStats& s = volumes_.stats().frames.back();
      status_ = std::to_string(s.volumes) + " volumes, " + std::to_string(s.silhouetteEdges) +
                " silhouette edges";
      return image;
    }
    case ViewMethod::kRadiosity: {
      if (!radiosity_) radiosity_ = std::make_unique<RadiositySolver>(radiosityOptions_);
      if (!radiosityIsCurrent_) {
        radiosity_->build(live_);
        radiosityMesh_ = radianceMesh(radiosity_->mesh());
        radiosityIsCurrent_ = true;
      }
      if (!meshRenderer_) meshRenderer_ = std::make_unique<MeshRenderer>();
      status_ = std::to_string(radiosityMesh_->indices.size() / 3) + " mesh triangles";
      return meshRenderer_->render(*radiosityMesh_, camera, width, height);
    }
    case ViewMethod::kCombined: {
      if (!combined_) combined_ = std::make_unique<CombinedSolution>(radiosityOptions_);
      if (!combinedIsCurrent_) {
        combined_->build(live_);
        combinedMesh_ = combinedMesh();
        combinedIsCurrent_ = true;
      }
      if (!combinedRenderer_) {
        MeshRenderer::Options drawing;
        drawing.unlitBackFaces = true;  // as the ray-traced image: back sides receive nothing
        combinedRenderer_ = std::make_unique<MeshRenderer>(drawing);
      }
      status_ = std::to_string(combinedMesh_->indices.size() / 3) + " mesh triangles";
      return combinedRenderer_->render(*combinedMesh_, camera, width, height);
    }
    case ViewMethod::kGalerkin: {
      if (!galerkin_)
        galerkin_ = std::make_unique<GalerkinRadiosity>(galerkinOptionsFrom(radiosityOptions_));
      if (!galerkinIsCurrent_) {
        galerkin_->build(live_);
        galerkinMesh_ = radianceMesh(galerkin_->leafMesh());
        galerkinIsCurrent_ = true;
      }
      if (!meshRenderer_) meshRenderer_ = std::make_unique<MeshRenderer>();
      status_ = std::to_string(galerkinMesh_->indices.size() / 3) + " leaf triangles";
      return meshRenderer_->render(*galerkinMesh_, camera, width, height);
    }
    case ViewMethod::kRaytrace: {
      // A view over the live pose and grid, as `penumbra render` makes it; made per image since
      // a grown extent replaces the grid.
      const ExactReference reference(live_.posed(), &live_.grid());
      RayTraceOptions options;
      options.width = width;
      options.height = height;
      options.threads = threads_;
      status_ = "exact reference per pixel";
      return renderRayTraced(live_.posed(), camera, live_.rays(), reference, options).radiance;
    }
  }
  return {};
}

}  // namespace penumbra::viewer
