#include "penumbra/render/ray_traced_image.h"

#include <cmath>
#include <numbers>
#include <random>

#include "penumbra/base/parallel_for.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/spatial/ray_caster.h"

namespace penumbra {

namespace {

struct PinholeFrame {
  Vec3 eye, forward, right, up;
  double tanHalfFovY, aspect;

  PinholeFrame(const Camera& c, int width, int height)
      : eye(c.eye),
        forward(normalize(c.target - c.eye)),
        right(normalize(cross(forward, c.up))),
        up(cross(right, forward)),
        tanHalfFovY(std::tan(c.fovYDegrees * std::numbers::pi / 360)),
        aspect(double(width) / height) {}

  // (sx, sy) in pixel units, y down from the top-left corner.
  Vec3 direction(double sx, double sy, int width, int height) const {
    const double ndcX = 2 * sx / width - 1, ndcY = 1 - 2 * sy / height;
    return normalize(forward + right * (ndcX * tanHalfFovY * aspect) + up * (ndcY * tanHalfFovY));
  }
};

}  // namespace

RayTracedImage renderRayTraced(const PosedScene& scene, const Camera& camera, const RayCaster& rays,
                               const ExactReference& reference, const RayTraceOptions& options) {
  return renderRayTraced(
      scene, camera, rays,
      [&](const Vec3& p, const Vec3& n, PolygonId polygon, std::uint64_t) {
        return reference.irradiance(p, n, polygon);
      },
      options);
}

RayTracedImage renderRayTraced(const PosedScene& scene, const Camera& camera, const RayCaster& rays,
                               const IrradianceAtHit& irradianceAt,
                               const RayTraceOptions& options) {
  const int w = options.width, h = options.height;
  RayTracedImage out{Image(w, h), Image(w, h)};
  const PinholeFrame frame(camera, w, h);
  const int spp = std::max(1, options.samplesPerPixel);
  const int strata = int(std::ceil(std::sqrt(double(spp))));

  parallelFor(h, options.threads, [&](long long y) {
    std::mt19937_64 rng(0x9E3779B97F4A7C15ull ^ (std::uint64_t(y) * 0xBF58476D1CE4E5B9ull));
    std::uniform_real_distribution<double> jitter(0, 1);
    for (int x = 0; x < w; ++x) {
      Rgb radiance, irradiance;
      for (int s = 0; s < spp; ++s) {
        double sx = x + 0.5, sy = y + 0.5;
        if (spp > 1) {
          sx = x + (s % strata + jitter(rng)) / strata;
          sy = y + (s / strata % strata + jitter(rng)) / strata;
        }
        const Vec3 dir = frame.direction(sx, sy, w, h);
        // Of a two-sided card, the side facing the eye.
        const auto hit = firstSurfaceSeen(rays, scene, frame.eye, dir, 0,
                                          std::numeric_limits<double>::infinity());
        if (!hit) continue;
        const WorldPolygon& polygon = scene.polygons[hit->polygon];
        if (dot(dir, polygon.plane.normal) >= 0) continue;  // back faces receive and emit nothing
        const Material& material = scene.materialOf(polygon);
        // Embree's hit point is single precision: put it back on the polygon's plane.
        const Vec3 p = polygon.plane.project(hit->point);
        const Rgb e = irradianceAt(
            p, polygon.plane.normal, polygon.id,
            (std::uint64_t(y) * std::uint64_t(w) + std::uint64_t(x)) * std::uint64_t(spp) +
                std::uint64_t(s));
        irradiance += e;
        radiance += (material.reflectance * e + material.emission) / std::numbers::pi;
      }
      out.radiance.at(x, int(y)) = radiance / spp;
      out.irradiance.at(x, int(y)) = irradiance / spp;
    }
    if (options.onRowDone) options.onRowDone(1);
  });
  return out;
}

}  // namespace penumbra
