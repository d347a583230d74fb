#pragma once
// Affine transforms x -> linear * x + translation, with inverse. Scene transforms are built as
// translate . rotate . scale (DESIGN.md §4).

#include "penumbra/geometry/quaternion.h"

namespace penumbra {

struct Transform {
  Mat3 linear;
  Vec3 translation;

  static Transform identity() { return {}; }
  static Transform fromTrs(const Vec3& translate, const Quaternion& rotate, const Vec3& scale) {
    return {rotate.toMatrix() * Mat3::diagonal(scale), translate};
  }

  Vec3 applyToPoint(const Vec3& p) const { return linear * p + translation; }
  Vec3 applyToVector(const Vec3& v) const { return linear * v; }
  // Normals transform by the inverse transpose; the result is not normalized.
  Vec3 applyToNormal(const Vec3& n) const { return linear.inverse().transposed() * n; }

  // this * other: apply `other` first.
  Transform operator*(const Transform& other) const {
    return {linear * other.linear, linear * other.translation + translation};
  }
  // Precondition: isInvertible().
  Transform inverse() const {
    const Mat3 inv = linear.inverse();
    return {inv, -(inv * translation)};
  }
  bool isInvertible() const { return linear.determinant() != 0; }
  // True when the transform flips orientation (mirrors), so polygon winding must be reversed.
  bool isReflection() const { return linear.determinant() < 0; }
};

}  // namespace penumbra
