#include "penumbra/radiosity/galerkin/linear_basis.h"

#include <algorithm>
#include <cmath>

#include "penumbra/geometry/polygon.h"

namespace penumbra {

ExactCubature quadraticCubature(const ElementShape& shape) {
  ExactCubature rule;
  const auto& v = shape.vertices;
  const auto addTriangle = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
    const double w = triangleArea(a, b, c) / 3;
    for (const Vec3& m : {(a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5}) {
      rule.points[rule.count] = m;
      rule.weights[rule.count++] = w;
    }
  };
  addTriangle(v[0], v[1], v[2]);
  if (shape.vertexCount == 4) addTriangle(v[0], v[2], v[3]);
  double total = 0;
  for (int i = 0; i < rule.count; ++i) total += rule.weights[i];
  for (int i = 0; i < rule.count; ++i) rule.weights[i] = total > 0 ? rule.weights[i] / total : 0;
  return rule;
}

LinearBasis::LinearBasis(const ElementShape& shape) {
  centroid_ = shape.centroid();
  const Vec3 edge = shape.vertices[1] - shape.vertices[0];
  u_ = normalize(edge - shape.normal * dot(edge, shape.normal));
  v_ = cross(shape.normal, u_);
  // Second moments about the centroid, exact (degree 2).
  double suu = 0, sut = 0, stt = 0;
  const ExactCubature rule = quadraticCubature(shape);
  for (int i = 0; i < rule.count; ++i) {
    const Vec3 d = rule.points[i] - centroid_;
    const double s = dot(d, u_), t = dot(d, v_);
    suu += rule.weights[i] * s * s;
    sut += rule.weights[i] * s * t;
    stt += rule.weights[i] * t * t;
  }
  // Gram-Schmidt of s, t against 1 (zero already: centroid) and each other. A sliver whose
  // second moment vanishes keeps zero linear functions (constant only).
  if (suu > 0) {
    a_ = 1 / std::sqrt(suu);
    const double residual = stt - sut * sut / suu;
    if (residual > 1e-12 * (suu + stt)) {
      c_ = 1 / std::sqrt(residual);
      b_ = -(sut / suu) * c_;
    }
  }
  for (int i = 0; i < shape.vertexCount; ++i) {
    const auto phi = at(shape.vertices[i]);
    reach_ = std::max({reach_, std::abs(phi[1]), std::abs(phi[2])});
  }
}

Cubature linkCubature(const ElementShape& shape) {
  Cubature rule;
  const auto& v = shape.vertices;
  if (shape.vertexCount == 3) {
    constexpr double kMajor = 2.0 / 3, kMinor = 1.0 / 6;
    rule.points[0] = v[0] * kMajor + v[1] * kMinor + v[2] * kMinor;
    rule.points[1] = v[0] * kMinor + v[1] * kMajor + v[2] * kMinor;
    rule.points[2] = v[0] * kMinor + v[1] * kMinor + v[2] * kMajor;
    rule.weights = {1.0 / 3, 1.0 / 3, 1.0 / 3, 0};
    rule.count = 3;
    return rule;
  }
  // Bilinear map p(s, t) = (1−s)(1−t) v0 + s(1−t) v1 + s t v2 + (1−s) t v3 on [0, 1]².
  const double g = 0.5 / std::sqrt(3.0);
  const std::array<double, 2> nodes{0.5 - g, 0.5 + g};
  double total = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const double s = nodes[i], t = nodes[j];
      const Vec3 p =
          v[0] * ((1 - s) * (1 - t)) + v[1] * (s * (1 - t)) + v[2] * (s * t) + v[3] * ((1 - s) * t);
      const Vec3 ds = (v[1] - v[0]) * (1 - t) + (v[2] - v[3]) * t;
      const Vec3 dt = (v[3] - v[0]) * (1 - s) + (v[2] - v[1]) * s;
      const double jacobian = length(cross(ds, dt));
      rule.points[rule.count] = p;
      rule.weights[rule.count++] = jacobian;
      total += jacobian;
    }
  for (int i = 0; i < rule.count; ++i) rule.weights[i] = total > 0 ? rule.weights[i] / total : 0;
  return rule;
}

BasisTransfer basisTransfer(const LinearBasis& parent, const LinearBasis& child,
                            const ElementShape& childShape) {
  BasisTransfer transfer{};
  const ExactCubature rule = quadraticCubature(childShape);
  for (int i = 0; i < rule.count; ++i) {
    const auto p = parent.at(rule.points[i]);
    const auto c = child.at(rule.points[i]);
    for (int beta = 0; beta < 3; ++beta)
      for (int alpha = 0; alpha < 3; ++alpha)
        transfer[beta][alpha] += rule.weights[i] * p[beta] * c[alpha];
  }
  return transfer;
}

LinearRgb restrictedToChild(const LinearRgb& parent, const BasisTransfer& transfer) {
  LinearRgb child{};
  for (int alpha = 0; alpha < 3; ++alpha)
    for (int beta = 0; beta < 3; ++beta) child[alpha] += parent[beta] * transfer[beta][alpha];
  return child;
}

void addProjectionToParent(LinearRgb& parent, const LinearRgb& child, const BasisTransfer& transfer,
                           double share) {
  for (int beta = 0; beta < 3; ++beta)
    for (int alpha = 0; alpha < 3; ++alpha)
      parent[beta] += child[alpha] * (share * transfer[beta][alpha]);
}

}  // namespace penumbra
