#pragma once
// Point samples over a polygonal area light, for soft shadows by jittering the light (McReynolds &
// Blythe §11.3.2.3; Heckbert & Herf, "Simulating Soft Shadows with Graphics Hardware", 1997).
//
// Stratified: the unit square is cut into a near-square grid of N cells with one jittered (seeded)
// point per cell, mapped onto the polygon by an area-preserving map (u picks the triangle by its
// share of the area and the position across it, v the position along it), so the strata have
// equal areas on the light. Each sample stands for area A / N.

#include <cstdint>
#include <vector>

#include "penumbra/geometry/polygon.h"

namespace penumbra {

// N samples on `polygon`. N == 1 gives the area centroid (hard shadows from the light's centre).
// Preconditions: n >= 1; the polygon is planar and simple with non-zero area.
std::vector<Vec3> stratifiedLightSamples(const Polygon3& polygon, int n, std::uint64_t seed = 1);

}  // namespace penumbra
