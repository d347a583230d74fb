#pragma once
// The exact form factor from a point to an element: the element clipped to the point's front
// half-space (Sutherland-Hodgman, on the stack: the solvers' innermost loop), then Lambert's
// formula as in lighting/form_factor.h.

#include "penumbra/radiosity/element.h"

namespace penumbra {

// From the point x (unit normal n) to the front side of s; 0 when x lies behind s.
double pointToElementFormFactor(const Vec3& x, const Vec3& n, const ElementShape& s);

}  // namespace penumbra
