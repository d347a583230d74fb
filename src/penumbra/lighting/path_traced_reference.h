#pragma once
// A Monte Carlo reference for total irradiance (direct + indirect) in diffuse scenes, independent
// of the engines: path tracing (Kajiya 1986) with exact next-event estimation.
//
// E(x) = E_direct(x) + ∫ ρ(y) E(y) cos θ / π dω, y the point met from x in direction ω (0 when
// none is met or it is met from behind: polygons reflect from their front side only). The direct
// part at x and at every path vertex is the exact reference's (DESIGN.md §5), so emission is
// never counted on a hit; directions are cosine-distributed, so each vertex adds the product of
// the reflectances met so far times its exact direct irradiance; paths end by Russian roulette on
// the reflectance (Arvo & Kirk 1990).

#include <cstdint>

#include "penumbra/base/rgb.h"
#include "penumbra/scene/posed_scene.h"

namespace penumbra {

class ExactReference;
class RayCaster;

struct PathTracedEstimate {
  Rgb direct;                 // exact (W/m²)
  Rgb indirect;               // the mean over the paths
  Rgb indirectStandardError;  // the paths' sample std / sqrt(paths)
  long long rays = 0;
};

class PathTracedReference {
 public:
  // Keeps references to all three, which must outlive it and come from the same scene.
  PathTracedReference(const PosedScene& scene, const RayCaster& caster,
                      const ExactReference& reference);

  // Irradiance at `point`, on polygon `receiver` with front normal `normal`, from `paths` paths.
  // Deterministic for a seed. Thread-safe.
  PathTracedEstimate irradiance(const Vec3& point, const Vec3& normal, PolygonId receiver,
                                int paths, std::uint64_t seed) const;

 private:
  const PosedScene& scene_;
  const RayCaster& caster_;
  const ExactReference& reference_;
};

}  // namespace penumbra
