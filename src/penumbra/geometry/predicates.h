#pragma once
// Exact geometric predicates (filtered floating point, exact fallback; CGAL Epick underneath).
// Signs are exact for the double inputs given: topology decisions must use these, not epsilons.

#include "penumbra/geometry/vec3.h"

namespace penumbra {

enum class Sign { kNegative = -1, kZero = 0, kPositive = 1 };

// Sign of det(b - a, c - a, d - a) = sign of dot((b - a) x (c - a), d - a): kPositive when d lies on
// the side that the normal (b - a) x (c - a) points to.
Sign orientation3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// Sign of cross(b - a, c - a): kPositive for a left turn.
Sign orientation2d(const Vec2& a, const Vec2& b, const Vec2& c);

}  // namespace penumbra
