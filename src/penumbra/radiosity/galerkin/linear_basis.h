#pragma once
// Linear functions over an element, in a basis orthonormal for the element's area-mean inner
// product <f, g> = (1/A) ∫ f g dA (Zatz 1993, "Galerkin radiosity"; Gortler et al. 1993). The
// first basis function is the constant 1, so a function's first coefficient is its area mean; the
// other two are linear, zero-mean. A function on the element is Σ_k c_k φ_k(x).
//
// Also the element's cubature rules: the points where a link samples its kernel (few, for speed)
// and an exact rule for quadratics (for the basis itself and the transfers between a parent's and
// a child's bases, which must be exact so that push-pull neither creates nor loses energy).

#include <array>
#include <cstdint>

#include "penumbra/base/rgb.h"
#include "penumbra/radiosity/element.h"

namespace penumbra {

// Coefficients of an RGB linear function in an element's basis.
using LinearRgb = std::array<Rgb, 3>;

class LinearBasis {
 public:
  LinearBasis() = default;
  explicit LinearBasis(const ElementShape& shape);

  // φ_0(x), φ_1(x), φ_2(x) at a point of the element's plane.
  std::array<double, 3> at(const Vec3& x) const {
    const Vec3 d = x - centroid_;
    const double s = dot(d, u_), t = dot(d, v_);
    return {1.0, a_ * s, b_ * s + c_ * t};
  }
  // Σ_k c_k φ_k(x).
  Rgb evaluate(const LinearRgb& c, const Vec3& x) const {
    const auto phi = at(x);
    return c[0] + c[1] * phi[1] + c[2] * phi[2];
  }
  // The largest |φ_1|, |φ_2| can reach over the element (a bound on how far a function strays
  // from its mean, per unit of its linear coefficients).
  double reach() const { return reach_; }
  const Vec3& centroid() const { return centroid_; }

 private:
  Vec3 centroid_, u_, v_;
  double a_ = 0, b_ = 0, c_ = 0;  // φ_1 = a s, φ_2 = b s + c t in the (u, v) frame
  double reach_ = 0;
};

// A cubature rule over an element: points with weights summing to 1 (area means).
struct Cubature {
  std::array<Vec3, 4> points{};
  std::array<double, 4> weights{};
  int count = 0;
};

// The rule a link samples its kernel with: 2 x 2 Gauss points in a quadrilateral's bilinear
// parameters (weighted by the map's Jacobian), the 3-point degree-2 rule (barycentric 2/3, 1/6,
// 1/6) in a triangle.
Cubature linkCubature(const ElementShape& shape);

// An exact rule for polynomials of degree 2 (edge midpoints of each triangle, a quadrilateral
// split along its diagonal): up to 6 points.
struct ExactCubature {
  std::array<Vec3, 6> points{};
  std::array<double, 6> weights{};
  int count = 0;
};
ExactCubature quadraticCubature(const ElementShape& shape);

// T[β][α] = <φ_parent,β, φ_child,α> over the child: a parent's linear function restricted to the
// child has coefficients c_child,α = Σ_β c_parent,β T[β][α], and the projection of a child's
// function onto the parent's basis receives (A_child / A_parent) Σ_α T[β][α] c_child,α.
using BasisTransfer = std::array<std::array<double, 3>, 3>;
BasisTransfer basisTransfer(const LinearBasis& parent, const LinearBasis& child,
                            const ElementShape& childShape);
// A parent's function restricted to a child: its coefficients in the child's basis.
LinearRgb restrictedToChild(const LinearRgb& parent, const BasisTransfer& transfer);
// Adds a child's function, the child covering `share` of the parent's area, to the projection
// onto the parent's basis being summed in `parent`.
void addProjectionToParent(LinearRgb& parent, const LinearRgb& child, const BasisTransfer& transfer,
                           double share);

}  // namespace penumbra
