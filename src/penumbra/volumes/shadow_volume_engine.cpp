#include "penumbra/volumes/shadow_volume_engine.h"

#include <chrono>
#include <cmath>

#include "penumbra/base/check.h"

namespace penumbra {

namespace {

bool isTranslation(const Transform& t) {
  const Mat3 identity;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (t.linear.m[i][j] != identity.m[i][j]) return false;
  return true;
}

Polygon3 transformed(const Polygon3& polygon, const Transform& transform) {
  Polygon3 out;
  out.reserve(polygon.size());
  for (const Vec3& p : polygon) out.push_back(transform.applyToPoint(p));
  return out;
}

void count(VolumeUpdateStats& stats, const std::vector<LightVolumes>& lights) {
  for (const LightVolumes& light : lights)
    for (const ObjectVolume& v : light.objects) {
      ++stats.volumes;
      stats.silhouetteEdges += static_cast<long long>(v.silhouetteEdges.size());
      stats.capTriangles += static_cast<long long>(v.capTriangles.size());
    }
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

ShadowVolumeEngine::ShadowVolumeEngine(const VolumeOptions& options) : options_(options) {
  CHECK_GE(options.baseW, 0);
}

int ShadowVolumeEngine::excludedPolygon(int light, int object) const {
  return lights_[light].objectIndex == object ? lightLocalPolygon_[light] : -1;
}

ObjectVolume ShadowVolumeEngine::rebuild(int light, int object) const {
  const ObjectState& state = objects_[object];
  return buildObjectVolume(state.mesh, transformed(state.mesh.vertices, state.transform),
                           lights_[light].position, options_.baseW, excludedPolygon(light, object));
}

void ShadowVolumeEngine::build(const Scene& scene, double frame) {
  buildWith(scene, transformsAt(scene, frame), frame);
}

void ShadowVolumeEngine::build(const DynamicScene& scene) {
  buildWith(scene.scene(), scene.posed().objectTransforms, scene.frame());
}

void ShadowVolumeEngine::update(const Scene& scene, double newFrame) {
  updateTo(scene, transformsAt(scene, newFrame), newFrame);
}

void ShadowVolumeEngine::update(const DynamicScene& scene, const SceneChange& change) {
  CHECK_EQ(change.frameAfter, scene.frame());
  updateTo(scene.scene(), scene.posed().objectTransforms, scene.frame());
}

void ShadowVolumeEngine::buildWith(const Scene& scene, const std::vector<Transform>& transforms,
                                   double frame) {
  CHECK_EQ(transforms.size(), scene.objects.size());
  const auto start = std::chrono::steady_clock::now();
  frame_ = frame;
  objects_.clear();
  lights_.clear();
  lightLocalPolygon_.clear();
  stats_ = {};
  PolygonId id = 0;
  for (int o = 0; o < int(scene.objects.size()); ++o) {
    const SceneObject& object = scene.objects[o];
    ObjectState state;
    state.transform = transforms[o];
    // The mesh's polygons are the object's own; a light polygon is excluded per light, so that
    // a light never shadows itself while it still shadows the other lights.
    state.mesh = buildOccluderMesh(object.polygons);
    for (int p = 0; p < int(object.polygons.size()); ++p, ++id) {
      if (!scene.materials[object.polygonMaterial[p]].isEmitter()) continue;
      LightVolumes light;
      light.polygon = id;
      light.objectIndex = o;
      light.worldPolygon = transformed(object.polygons[p], state.transform);
      light.position = centroid(light.worldPolygon);
      lights_.push_back(std::move(light));
      lightLocalPolygon_.push_back(p);
    }
    objects_.push_back(std::move(state));
  }
  anchors_.assign(lights_.size(), std::vector<Anchor>(objects_.size()));
  for (int l = 0; l < int(lights_.size()); ++l)
    for (int o = 0; o < int(objects_.size()); ++o) lights_[l].objects.push_back(rebuild(l, o));
  VolumeUpdateStats s;
  s.frame = frame;
  count(s, lights_);
  s.rebuilds = s.volumes;
  s.seconds = secondsSince(start);
  stats_.frames.push_back(s);
}

void ShadowVolumeEngine::updateTo(const Scene& scene, const std::vector<Transform>& targets,
                                  double newFrame) {
  CHECK_EQ(scene.objects.size(), objects_.size());
  CHECK_EQ(targets.size(), objects_.size());
  const auto start = std::chrono::steady_clock::now();
  VolumeUpdateStats s;
  s.frame = newFrame;

  // Object deltas first: delta = new * old^-1 moves the occluder-attached vertices.
  std::vector<Transform> deltas(objects_.size());
  std::vector<char> moved(objects_.size(), 0), linear(objects_.size(), 0);
  std::vector<Transform> newTransforms(objects_.size());
  for (int o = 0; o < int(objects_.size()); ++o) {
    ObjectState& state = objects_[o];
    newTransforms[o] = targets[o];
    if (isSameTransform(newTransforms[o], state.transform)) {
      state.hasLinearStep = false;
      continue;
    }
    moved[o] = 1;
    // Pure translation when the linear parts agree exactly: the delta is then exact too.
    bool sameLinear = true;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        sameLinear =
            sameLinear && newTransforms[o].linear.m[i][j] == state.transform.linear.m[i][j];
    if (sameLinear) {
      const Vec3 t = newTransforms[o].translation - state.transform.translation;
      deltas[o] = Transform{Mat3{}, t};
      const double scale = length(t);
      linear[o] = state.hasLinearStep && length(t - state.linearStep) <= 1e-12 * scale;
      state.hasLinearStep = true;
      state.linearStep = t;
    } else {
      deltas[o] = newTransforms[o] * state.transform.inverse();
      state.hasLinearStep = false;
    }
  }

  for (int l = 0; l < int(lights_.size()); ++l) {
    LightVolumes& light = lights_[l];
    const int lightObject = light.objectIndex;
    const Polygon3 polygon = transformed(scene.objects[lightObject].polygons[lightLocalPolygon_[l]],
                                         newTransforms[lightObject]);
    const Vec3 newPosition = centroid(polygon);
    const Vec3 d = newPosition - light.position;
    const bool lightMoved = !(d == Vec3{});
    light.worldPolygon = polygon;
    for (int o = 0; o < int(objects_.size()); ++o) {
      ObjectVolume& volume = light.objects[o];
      Anchor& anchor = anchors_[l][o];
      if (!moved[o] && !lightMoved) {
        ++s.unchanged;
        continue;
      }
      // The occluder-attached vertices move with the occluder; the silhouette is kept if every
      // polygon faces the (new) light as before.
      std::vector<Vec3> near = volume.nearVertices;
      if (moved[o]) near = transformed(near, deltas[o]);
      if (facingSignature(objects_[o].mesh, near, newPosition, excludedPolygon(l, o)) !=
          volume.facing) {
        ObjectState& state = objects_[o];
        const Transform old = state.transform;
        state.transform = newTransforms[o];
        const Vec3 oldPosition = light.position;
        light.position = newPosition;
        volume = rebuild(l, o);
        light.position = oldPosition;
        state.transform = old;
        anchor.steps = 0;
        ++s.rebuilds;
        continue;
      }
      if (lightMoved) {
        translateLight(volume, d);
        ++s.lightMoves;
      }
      if (moved[o]) {
        ++s.occluderMoves;
        if (linear[o] && !lightMoved && anchor.steps > 0) {
          // Simplified form for linear motion: positions from the start of the run, n equal steps
          // later; no transform inverse, and no rounding drift from step to step.
          ++anchor.steps;
          const Vec3 offset = deltas[o].translation * double(anchor.steps);
          for (size_t i = 0; i < near.size(); ++i) {
            volume.nearVertices[i] = anchor.nearVertices[i] + offset;
            volume.baseVertices[i] = anchor.baseVertices[i] + offset;
          }
          ++s.linearMoves;
        } else {
          // Anchor the run at the positions before this step.
          anchor.nearVertices = volume.nearVertices;
          anchor.baseVertices = volume.baseVertices;
          anchor.steps = 1;
          moveOccluder(volume, deltas[o], newPosition);
          if (!isTranslation(deltas[o]) || lightMoved) anchor.steps = 0;
        }
      }
    }
    light.position = newPosition;
  }
  for (int o = 0; o < int(objects_.size()); ++o) objects_[o].transform = newTransforms[o];
  frame_ = newFrame;
  count(s, lights_);
  s.seconds = secondsSince(start);
  stats_.frames.push_back(s);
}

void ShadowVolumeEngine::moveLight(int light, const Vec3& position) {
  CHECK(light >= 0 && light < int(lights_.size()));
  LightVolumes& lv = lights_[light];
  const Vec3 d = position - lv.position;
  if (d == Vec3{}) return;
  lv.position = position;
  for (int o = 0; o < int(objects_.size()); ++o) {
    ObjectVolume& volume = lv.objects[o];
    anchors_[light][o].steps = 0;
    if (facingSignature(objects_[o].mesh, volume.nearVertices, position,
                        excludedPolygon(light, o)) != volume.facing) {
      volume = rebuild(light, o);
      ++stats_.jitterRebuilds;
    } else {
      translateLight(volume, d);
      ++stats_.jitterIncremental;
    }
  }
}

}  // namespace penumbra
