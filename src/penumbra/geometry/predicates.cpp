#include "penumbra/geometry/predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace penumbra {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

Sign toSign(CGAL::Orientation o) {
  return o == CGAL::POSITIVE ? Sign::kPositive
                             : (o == CGAL::NEGATIVE ? Sign::kNegative : Sign::kZero);
}
Kernel::Point_3 toCgal(const Vec3& p) { return {p.x, p.y, p.z}; }
}  // namespace

Sign orientation3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return toSign(CGAL::orientation(toCgal(a), toCgal(b), toCgal(c), toCgal(d)));
}

Sign orientation2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  return toSign(CGAL::orientation(Kernel::Point_2(a.x, a.y), Kernel::Point_2(b.x, b.y),
                                  Kernel::Point_2(c.x, c.y)));
}

}  // namespace penumbra
