#pragma once
// Unit quaternions for rotations: axis-angle construction, composition, slerp (keyframe motion).

#include <cmath>

#include "penumbra/geometry/mat3.h"

namespace penumbra {

struct Quaternion {
  double w = 1, x = 0, y = 0, z = 0;

  static Quaternion identity() { return {}; }
  // Precondition: axis is not the zero vector.
  static Quaternion fromAxisAngle(const Vec3& axis, double radians) {
    const Vec3 a = normalize(axis);
    const double s = std::sin(radians / 2);
    return {std::cos(radians / 2), a.x * s, a.y * s, a.z * s};
  }

  Quaternion operator*(const Quaternion& q) const {
    return {w * q.w - x * q.x - y * q.y - z * q.z, w * q.x + x * q.w + y * q.z - z * q.y,
            w * q.y - x * q.z + y * q.w + z * q.x, w * q.z + x * q.y - y * q.x + z * q.w};
  }
  double dotWith(const Quaternion& q) const { return w * q.w + x * q.x + y * q.y + z * q.z; }
  Quaternion normalized() const {
    const double n = std::sqrt(dotWith(*this));
    return {w / n, x / n, y / n, z / n};
  }

  Mat3 toMatrix() const {
    Mat3 r;
    r.m[0][0] = 1 - 2 * (y * y + z * z);
    r.m[0][1] = 2 * (x * y - w * z);
    r.m[0][2] = 2 * (x * z + w * y);
    r.m[1][0] = 2 * (x * y + w * z);
    r.m[1][1] = 1 - 2 * (x * x + z * z);
    r.m[1][2] = 2 * (y * z - w * x);
    r.m[2][0] = 2 * (x * z - w * y);
    r.m[2][1] = 2 * (y * z + w * x);
    r.m[2][2] = 1 - 2 * (x * x + y * y);
    return r;
  }
};

// Spherical linear interpolation along the shorter arc; t in [0, 1].
inline Quaternion slerp(const Quaternion& a, Quaternion b, double t) {
  double cosTheta = a.dotWith(b);
  if (cosTheta < 0) {
    b = {-b.w, -b.x, -b.y, -b.z};
    cosTheta = -cosTheta;
  }
  double wa, wb;
  if (cosTheta > 0.9995) {  // nearly parallel: linear interpolation is accurate and stable
    wa = 1 - t;
    wb = t;
  } else {
    const double theta = std::acos(cosTheta);
    const double sinTheta = std::sin(theta);
    wa = std::sin((1 - t) * theta) / sinTheta;
    wb = std::sin(t * theta) / sinTheta;
  }
  return Quaternion{wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y,
                    wa * a.z + wb * b.z}
      .normalized();
}

}  // namespace penumbra
