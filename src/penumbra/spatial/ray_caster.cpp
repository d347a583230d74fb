// Ray casting with Embree 3.
// References:
//  - I. Wald, S. Woop, C. Benthin, G. S. Johnson, M. Ernst, "Embree: A Kernel Framework for
//    Efficient CPU Ray Tracing", ACM TOG 33(4), 2014; Embree 3 API manual (rtcore.h): robust scene
//    flag, context filter functions, build quality.
//  - M. Pharr, W. Jakob, G. Humphreys, "Physically Based Rendering", 3rd/4th ed., §3.9 (managing
//    rounding error; why self-intersection needs a tolerance relative to the scene's magnitude).

#include "penumbra/spatial/ray_caster.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "penumbra/base/check.h"
#include "penumbra/geometry/triangulation.h"

namespace penumbra {

namespace {

struct DeviceDeleter {
  void operator()(RTCDevice device) const { rtcReleaseDevice(device); }
};
struct SceneDeleter {
  void operator()(RTCScene scene) const { rtcReleaseScene(scene); }
};
using DeviceHandle = std::unique_ptr<RTCDeviceTy, DeviceDeleter>;
using SceneHandle = std::unique_ptr<RTCSceneTy, SceneDeleter>;

std::string describeError(RTCError error) {
  switch (error) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
    default:
      return "unknown error";
  }
}

void throwIfFailed(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree: ") + what + ": " + describeError(error));
}

}  // namespace

struct RayCaster::Impl {
  DeviceHandle device;
  SceneHandle scene;  // top level: one identity instance per object with triangles
  std::vector<SceneHandle> objectScenes;  // indexed by object; null where it has no triangles
  Vec3 center;                            // Embree coordinates are world coordinates minus this
  double epsilon = 0;                     // absolute distance tolerance
  // Polygon of each triangle, per object (Embree's instance id is the object index).
  std::vector<std::vector<PolygonId>> triangleToPolygon;
  std::vector<Plane> planes;  // indexed by PolygonId, double precision
  int triangles = 0;

  Vec3 toLocal(const Vec3& p) const { return p - center; }
  PolygonId polygonOf(unsigned instance, unsigned primitive) const {
    return triangleToPolygon[instance][primitive];
  }
  // (Re)builds object `o`'s Embree scene from the posed polygons and attaches its instance.
  void buildObject(const PosedScene& posed, int o);
};

namespace {

// Per-query state for the context filter. Embree hands the filter the RTCIntersectContext pointer
// we passed in, so the query data rides behind it (standard layout, context first).
struct QueryContext {
  RTCIntersectContext base;
  const RayCaster::Impl* impl;
  PolygonId ignored;      // never hit, or kNoPolygon
  bool excludeEndpoints;  // segment query: drop polygons whose plane holds an endpoint
  Vec3 from, to;
};

void queryFilter(const RTCFilterFunctionNArguments* args) {
  const auto* query = reinterpret_cast<const QueryContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const PolygonId polygon = query->impl->polygonOf(RTCHitN_instID(args->hit, args->N, i, 0),
                                                     RTCHitN_primID(args->hit, args->N, i));
    if (polygon == query->ignored) {
      args->valid[i] = 0;
      continue;
    }
    if (query->excludeEndpoints) {
      const Plane& plane = query->impl->planes[polygon];
      if (std::abs(plane.signedDistance(query->from)) <= query->impl->epsilon ||
          std::abs(plane.signedDistance(query->to)) <= query->impl->epsilon)
        args->valid[i] = 0;
    }
  }
}

QueryContext makeContext(const RayCaster::Impl& impl, PolygonId ignored) {
  QueryContext context;
  rtcInitIntersectContext(&context.base);
  // No filter call per candidate hit unless there is something to filter.
  context.base.filter = ignored == RayCaster::kNoPolygon ? nullptr : queryFilter;
  context.impl = &impl;
  context.ignored = ignored;
  context.excludeEndpoints = false;
  return context;
}

// Robust: watertight traversal, no cracks between the triangles of a polygon or between polygons
// sharing an edge. High quality: each structure is queried far more often than it is rebuilt.
void setSceneFlags(RTCScene scene) {
  rtcSetSceneFlags(scene,
                   RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
}

}  // namespace

void RayCaster::Impl::buildObject(const PosedScene& posed, int o) {
  RTCDevice dev = device.get();
  RTCScene top = scene.get();
  if (objectScenes[o]) {
    rtcDetachGeometry(top, unsigned(o));
    objectScenes[o].reset();
  }
  triangles -= int(triangleToPolygon[o].size());
  triangleToPolygon[o].clear();
  // Triangulate every polygon; vertices shared within a polygon so its triangles meet exactly.
  std::vector<float> vertices;
  std::vector<unsigned> indices;
  for (PolygonId id = posed.objectFirstPolygon[o]; id < posed.objectFirstPolygon[o + 1]; ++id) {
    const WorldPolygon& polygon = posed.polygons[id];
    planes[id] = polygon.plane;
    const unsigned base = unsigned(vertices.size() / 3);
    const auto polygonTriangles = triangulate(polygon.vertices);
    if (polygonTriangles.empty()) continue;
    for (const Vec3& v : polygon.vertices) {
      const Vec3 local = toLocal(v);
      vertices.insert(vertices.end(), {float(local.x), float(local.y), float(local.z)});
    }
    for (const auto& t : polygonTriangles) {
      indices.insert(indices.end(),
                     {base + unsigned(t[0]), base + unsigned(t[1]), base + unsigned(t[2])});
      triangleToPolygon[o].push_back(id);
    }
  }
  triangles += int(triangleToPolygon[o].size());
  if (indices.empty()) return;

  objectScenes[o].reset(rtcNewScene(dev));
  throwIfFailed(dev, "rtcNewScene");
  RTCScene objectScene = objectScenes[o].get();
  setSceneFlags(objectScene);
  RTCGeometry geometry = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  const size_t vertexCount = vertices.size() / 3, triangleCount = indices.size() / 3;
  // rtcSetNewGeometryBuffer allocates with the padding Embree's SIMD loads need.
  auto* vertexBuffer = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertexCount));
  auto* indexBuffer = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangleCount));
  throwIfFailed(dev, "allocating geometry buffers");
  std::copy(vertices.begin(), vertices.end(), vertexBuffer);
  std::copy(indices.begin(), indices.end(), indexBuffer);
  rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
  rtcCommitGeometry(geometry);
  rtcAttachGeometryByID(objectScene, geometry, 0);
  rtcReleaseGeometry(geometry);  // the scene holds its own reference
  rtcCommitScene(objectScene);
  throwIfFailed(dev, "rtcCommitScene (object)");

  // The identity instance: rays reach the object's triangles unchanged (multiplying by 1 and adding
  // 0 is exact in float), so hits are those of one flat scene.
  RTCGeometry instance = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(instance, objectScene);
  const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
  rtcCommitGeometry(instance);
  rtcAttachGeometryByID(top, instance, unsigned(o));
  rtcReleaseGeometry(instance);
  throwIfFailed(dev, "attaching an object instance");
}

RayCaster::RayCaster(const PosedScene& scene) : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  impl.device.reset(rtcNewDevice("verbose=0"));
  if (!impl.device)
    throw std::runtime_error("Embree: cannot create a device: " +
                             describeError(rtcGetDeviceError(nullptr)));
  RTCDevice device = impl.device.get();
  // Polygons are opaque from both sides and the endpoint rule needs a filter: refuse a build of
  // Embree that would silently drop either.
  if (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED) != 0)
    throw std::runtime_error("Embree was built with back-face culling; two-sided hits are needed");
  if (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED) == 0)
    throw std::runtime_error("Embree was built without filter functions");

  const Box3& extent = scene.extent.isEmpty() ? scene.bounds : scene.extent;
  impl.center = extent.isEmpty() ? Vec3{} : extent.center();
  const double size = extent.diagonalLength();
  impl.epsilon = kRelativeEpsilon * (size > 0 ? size : 1.0);

  impl.scene.reset(rtcNewScene(device));
  throwIfFailed(device, "rtcNewScene");
  setSceneFlags(impl.scene.get());
  impl.planes.resize(scene.polygons.size());
  const int objects = scene.objectCount();
  impl.objectScenes.resize(objects);
  impl.triangleToPolygon.resize(objects);
  for (int o = 0; o < objects; ++o) impl.buildObject(scene, o);
  rtcCommitScene(impl.scene.get());
  throwIfFailed(device, "rtcCommitScene");
}

void RayCaster::moveObjects(const PosedScene& scene, const std::vector<int>& objects) {
  Impl& impl = *impl_;
  for (int object : objects) {
    CHECK(object >= 0 && object < int(impl.objectScenes.size()));
    impl.buildObject(scene, object);
  }
  rtcCommitScene(impl.scene.get());
  throwIfFailed(impl.device.get(), "rtcCommitScene");
}

RayCaster::~RayCaster() = default;
RayCaster::RayCaster(RayCaster&&) noexcept = default;
RayCaster& RayCaster::operator=(RayCaster&&) noexcept = default;

double RayCaster::epsilon() const {
  return impl_->epsilon;
}
int RayCaster::triangleCount() const {
  return impl_->triangles;
}

std::optional<RayHit> RayCaster::intersect(const Vec3& origin, const Vec3& direction, double tMin,
                                           double tMax, PolygonId ignored) const {
  DCHECK(squaredLength(direction) > 0);
  DCHECK(0 <= tMin && tMin <= tMax);
  const Impl& impl = *impl_;
  QueryContext context = makeContext(impl, ignored);
  const Vec3 o = impl.toLocal(origin);
  RTCRayHit rayHit;
  rayHit.ray.org_x = float(o.x);
  rayHit.ray.org_y = float(o.y);
  rayHit.ray.org_z = float(o.z);
  rayHit.ray.dir_x = float(direction.x);
  rayHit.ray.dir_y = float(direction.y);
  rayHit.ray.dir_z = float(direction.z);
  rayHit.ray.tnear = float(tMin);
  rayHit.ray.tfar = tMax >= double(std::numeric_limits<float>::max())
                        ? std::numeric_limits<float>::infinity()
                        : float(tMax);
  rayHit.ray.time = 0;
  rayHit.ray.mask = ~0u;
  rayHit.ray.id = 0;
  rayHit.ray.flags = 0;
  rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayHit.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl.scene.get(), &context.base, &rayHit);
  if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;

  RayHit hit;
  hit.polygon = impl.polygonOf(rayHit.hit.instID[0], rayHit.hit.primID);
  // Embree found the polygon; the parameter comes from the polygon's double-precision plane unless
  // the ray is too grazing for that to be better conditioned than Embree's float t.
  double t = rayHit.ray.tfar;
  const Plane& plane = impl.planes[hit.polygon];
  const double along = dot(plane.normal, direction);
  const double refined = -plane.signedDistance(origin) / along;
  const double slack = 16 * impl.epsilon / length(direction) + 1e-4 * std::abs(t);
  if (std::isfinite(refined) && std::abs(refined - t) <= slack) t = refined;
  hit.t = std::clamp(t, tMin, tMax);
  hit.point = origin + direction * hit.t;
  return hit;
}

bool RayCaster::isOccluded(const Vec3& from, const Vec3& to) const {
  if (from == to) return false;
  const Impl& impl = *impl_;
  QueryContext context = makeContext(impl, kNoPolygon);
  context.base.filter = queryFilter;
  context.excludeEndpoints = true;
  context.from = from;
  context.to = to;
  const Vec3 o = impl.toLocal(from);
  const Vec3 d = to - from;
  RTCRay ray;
  ray.org_x = float(o.x);
  ray.org_y = float(o.y);
  ray.org_z = float(o.z);
  ray.dir_x = float(d.x);
  ray.dir_y = float(d.y);
  ray.dir_z = float(d.z);
  // The whole closed segment: hits at the endpoints themselves are removed by the plane rule in
  // the filter, which unlike a parametric margin does not depend on the angle of incidence.
  ray.tnear = 0;
  ray.tfar = 1;
  ray.time = 0;
  ray.mask = ~0u;
  ray.id = 0;
  ray.flags = 0;
  rtcOccluded1(impl.scene.get(), &context.base, &ray);
  // Embree marks an occluded ray by setting tfar to -inf.
  return ray.tfar < 0;
}

std::optional<RayHit> firstSurfaceSeen(const RayCaster& rays, const PosedScene& scene,
                                       const Vec3& origin, const Vec3& direction, double tMin,
                                       double tMax, PolygonId ignored) {
  std::optional<RayHit> hit = rays.intersect(origin, direction, tMin, tMax, ignored);
  if (hit && dot(scene.polygons[hit->polygon].plane.normal, direction) >= 0) {
    const auto twin = rays.intersect(origin, direction, tMin,
                                     std::min(tMax, hit->t + rays.epsilon()), hit->polygon);
    const Vec3& normal = scene.polygons[hit->polygon].plane.normal;
    if (twin && twin->t >= hit->t - rays.epsilon() &&
        dot(scene.polygons[twin->polygon].plane.normal, normal) <= -1 + 1e-9)
      hit = twin;
  }
  return hit;
}

}  // namespace penumbra
