#pragma once
// A Monte Carlo reference for total irradiance (direct + indirect) in diffuse scenes, independent
// of the engines: path tracing (Kajiya 1986) with exact next-event estimation.
//
// E(x) = E_direct(x) + ∫ ρ(y) E(y) cos θ / π dω, y the point met from x in direction ω (0 when
// none is met or it is met from behind: polygons reflect from their front side only). Emission is
// never counted on a hit: the direct part at x and at every path vertex comes from next-event
// estimation; directions are cosine-distributed, so each vertex adds the product of the
// reflectances met so far times its direct irradiance; paths end by Russian roulette on the
// reflectance (Arvo & Kirk 1990).
//
// The direct part, two ways:
//  - exact (with an ExactReference): the exact reference's (DESIGN.md §5) at x and every vertex;
//    the least noise, but it shares its visibility code (polygon clipping) with the engines that
//    use it (the radiosity solver's exact visible form factors);
//  - sampled (without one): at x and every vertex one emitting polygon drawn in proportion to its
//    power, a point uniform on it and a shadow ray through the ray caster: visibility of its own,
//    independent of every engine's, for checking them.

#include <cstdint>
#include <vector>

#include "penumbra/base/rgb.h"
#include "penumbra/scene/posed_scene.h"

namespace penumbra {

class ExactReference;
class RayCaster;
class SplitMix;

struct PathTracedEstimate {
  Rgb direct;                 // exact, or the mean over the paths when sampled (W/m²)
  Rgb directStandardError;    // 0 when exact
  Rgb indirect;               // the mean over the paths
  Rgb indirectStandardError;  // the paths' sample std / sqrt(paths)
  long long rays = 0;
  Rgb total() const { return direct + indirect; }
  // Of direct + indirect (the two are estimated from the same paths: their covariance counts).
  Rgb totalStandardError;
};

class PathTracedReference {
 public:
  // Exact direct light. Keeps references to all three, which must outlive it and come from the
  // same scene.
  PathTracedReference(const PosedScene& scene, const RayCaster& caster,
                      const ExactReference& reference);
  // Sampled direct light, visibility by the ray caster's shadow rays only.
  PathTracedReference(const PosedScene& scene, const RayCaster& caster);

  // Irradiance at `point`, on polygon `receiver` with front normal `normal`, from `paths` paths.
  // Deterministic for a seed. Thread-safe.
  PathTracedEstimate irradiance(const Vec3& point, const Vec3& normal, PolygonId receiver,
                                int paths, std::uint64_t seed) const;

 private:
  // The direct irradiance at y (normal n, on polygon `on`): exact, or one light sample.
  Rgb direct(const Vec3& y, const Vec3& n, PolygonId on, SplitMix& rng) const;

  const PosedScene& scene_;
  const RayCaster& caster_;
  const ExactReference* reference_ = nullptr;  // null: sampled direct light
  // Emitting polygons and their cumulative power (largest channel of M × area), for sampling.
  std::vector<PolygonId> emitters_;
  std::vector<double> cumulativePower_;
};

}  // namespace penumbra
