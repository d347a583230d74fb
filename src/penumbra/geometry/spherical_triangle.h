#pragma once
// Arvo 1995, "Stratified sampling of spherical triangles": a direction uniform in the solid angle
// of the triangle (a, b, c) seen from x, from two numbers in [0, 1), and that solid angle.

#include <optional>

#include "penumbra/geometry/vec3.h"

namespace penumbra {

// The direction, or nothing when the triangle is degenerate seen from x; `solidAngle`, when
// given, receives the triangle's solid angle (steradians) even then.
std::optional<Vec3> sampleSphericalTriangle(const Vec3& x, const Vec3& a, const Vec3& b,
                                            const Vec3& c, double u1, double u2,
                                            double* solidAngle = nullptr);

}  // namespace penumbra
