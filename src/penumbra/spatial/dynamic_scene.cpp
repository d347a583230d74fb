#include "penumbra/spatial/dynamic_scene.h"

#include <chrono>

#include "penumbra/base/check.h"
#include "penumbra/scene/reach_bounds.h"

namespace penumbra {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool objectEmits(const Scene& scene, int object) {
  for (int material : scene.objects[object].polygonMaterial)
    if (scene.materials[material].isEmitter()) return true;
  return false;
}

bool contains(const Box3& outer, const Box3& inner) {
  return inner.isEmpty() || (outer.contains(inner.min) && outer.contains(inner.max));
}

Scene sceneOf(const PosedScene& posed) {
  Scene scene;
  scene.materials = posed.materials;
  for (const WorldPolygon& wp : posed.polygons) {
    CHECK_GE(wp.objectIndex, int(scene.objects.size()) - 1);
    while (int(scene.objects.size()) <= wp.objectIndex) {
      scene.objects.push_back({});
      scene.objects.back().name = "object " + std::to_string(scene.objects.size() - 1);
    }
    SceneObject& object = scene.objects[wp.objectIndex];
    object.polygons.push_back(wp.vertices);
    object.polygonMaterial.push_back(wp.material);
    object.polygonOrigin.push_back("polygon " + std::to_string(wp.id));
  }
  return scene;
}

}  // namespace

DynamicScene::DynamicScene(const Scene& scene, double frame)
    : DynamicScene(scene, transformsAt(scene, frame), reachBounds(scene), frame) {}

DynamicScene::DynamicScene(const Scene& scene, std::vector<Transform> transforms,
                           const Box3& extent, double frame)
    : scene_(scene),
      posed_(poseWith(scene_, std::move(transforms), extent, frame)),
      modifications_(scene_.objects.size(), 0) {
  buildStructures();
}

DynamicScene::DynamicScene(const PosedScene& posed) : scene_(sceneOf(posed)) {
  std::vector<Transform> identities(scene_.objects.size(), Transform::identity());
  posed_ = poseWith(scene_, std::move(identities), posed.extent, posed.frame);
  modifications_.assign(scene_.objects.size(), 0);
  buildStructures();
}

DynamicScene::~DynamicScene() = default;

void DynamicScene::buildStructures() {
  auto start = std::chrono::steady_clock::now();
  grid_ = std::make_unique<UniformGrid>(posed_);
  lastGridSeconds_ = secondsSince(start);
  start = std::chrono::steady_clock::now();
  rays_ = std::make_unique<RayCaster>(posed_);
  lastRaySeconds_ = secondsSince(start);
}

ObjectMove DynamicScene::makeMove(int object, const Transform& after) const {
  const SceneObject& o = scene_.objects[object];
  ObjectMove move;
  move.object = object;
  move.before = posed_.objectTransforms[object];
  move.after = after;
  move.boundsBefore = transformedBounds(o.polygons, move.before);
  move.boundsAfter = transformedBounds(o.polygons, move.after);
  // A caller's move is a jump: no poses in between. Keyframe steps add their sweep.
  move.swept = move.boundsBefore;
  move.swept.extend(move.boundsAfter);
  move.carriesLight = objectEmits(scene_, object);
  return move;
}

SceneChange DynamicScene::changeToFrame(double frame) const {
  SceneChange change;
  change.frameBefore = posed_.frame;
  change.frameAfter = frame;
  for (int o = 0; o < int(scene_.objects.size()); ++o) {
    const Transform after = scene_.objects[o].transformAt(frame);
    if (isSameTransform(after, posed_.objectTransforms[o])) continue;
    change.moves.push_back(makeMove(o, after));
    change.moves.back().swept.extend(sweptBounds(scene_.objects[o], posed_.frame, frame));
    // A caller's move may have left the keyframes' reach; going back is inside the extent.
    change.extentGrows = change.extentGrows || !contains(posed_.extent, change.moves.back().swept);
  }
  return change;
}

SceneChange DynamicScene::changeMoving(int object, const Transform& transform) const {
  CHECK(object >= 0 && object < int(scene_.objects.size()));
  CHECK(transform.isInvertible());
  SceneChange change;
  change.frameBefore = change.frameAfter = posed_.frame;
  if (isSameTransform(transform, posed_.objectTransforms[object])) return change;
  change.moves.push_back(makeMove(object, transform));
  change.extentGrows = !contains(posed_.extent, change.moves.back().swept);
  return change;
}

void DynamicScene::apply(const SceneChange& change) {
  CHECK_EQ(change.frameBefore, posed_.frame);
  for (const ObjectMove& move : change.moves) {
    CHECK(isSameTransform(move.before, posed_.objectTransforms[move.object]));
    ++modifications_[move.object];
  }
  if (change.extentGrows) {
    applyMoves(scene_, change, posed_);
    posed_.frame = change.frameAfter;
    // Grow by a quarter of the new size on every side so that a continuing drag does not re-grid
    // at every step.
    Box3 extent = posed_.extent;
    for (const ObjectMove& move : change.moves) extent.extend(move.swept);
    posed_.extent = extent.expanded(0.25 * extent.diagonalLength());
    buildStructures();
    return;
  }
  auto start = std::chrono::steady_clock::now();
  for (const ObjectMove& move : change.moves) grid_->removeObject(posed_, move.object);
  double gridSeconds = secondsSince(start);
  applyMoves(scene_, change, posed_);
  posed_.frame = change.frameAfter;
  start = std::chrono::steady_clock::now();
  for (const ObjectMove& move : change.moves) grid_->insertObject(posed_, move.object);
  lastGridSeconds_ = gridSeconds + secondsSince(start);
  start = std::chrono::steady_clock::now();
  std::vector<int> moved;
  for (const ObjectMove& move : change.moves) moved.push_back(move.object);
  rays_->moveObjects(posed_, moved);
  lastRaySeconds_ = secondsSince(start);
}

}  // namespace penumbra
