#pragma once
// Differential-area-to-polygon form factor by Lambert's formula (Lambert 1760; Baum, Rushmeier &
// Winget 1989, "Improving radiosity solutions through the use of analytically determined form
// factors"; Nishita & Nakamae 1985):
//   F = 1/(2π) Σ_i γ_i (n · Γ_i),  γ_i = ∠(R_i, R_{i+1}),  Γ_i = unit(R_{i+1} × R_i),  R_i = v_i − p.
// With this sign convention a loop whose front side faces p (counter-clockwise seen from p)
// contributes positively and a clockwise loop (a hole) negatively, so the form factor of a region
// with holes is the sum over its rings.

#include "penumbra/geometry/polygon.h"

namespace penumbra {

// Precondition: n is a unit vector; the loop lies in the closed half-space n·(x − p) >= 0 (clip it
// first: Lambert's formula is only the cosine-weighted solid angle for such loops).
double pointToPolygonFormFactor(const Vec3& p, const Vec3& n, const Polygon3& loop);

}  // namespace penumbra
