#pragma once
// Row-major 4x4 matrices in double precision for view and projection transforms (like Mat3,
// m[row][col]); columnMajorFloats() gives the layout glUniformMatrix4fv expects.

#include <array>

#include "penumbra/geometry/vec3.h"

namespace penumbra {

struct Vec4 {
  double x = 0, y = 0, z = 0, w = 0;

  constexpr Vec4() = default;
  constexpr Vec4(double vx, double vy, double vz, double vw) : x(vx), y(vy), z(vz), w(vw) {}
  constexpr Vec4(const Vec3& v, double vw) : x(v.x), y(v.y), z(v.z), w(vw) {}
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : (i == 2 ? z : w)); }
  constexpr bool operator==(const Vec4&) const = default;
};

struct Mat4 {
  double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};

  static constexpr Mat4 identity() { return {}; }

  constexpr Vec4 operator*(const Vec4& v) const {
    Vec4 r;
    r.x = m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z + m[0][3] * v.w;
    r.y = m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z + m[1][3] * v.w;
    r.z = m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z + m[2][3] * v.w;
    r.w = m[3][0] * v.x + m[3][1] * v.y + m[3][2] * v.z + m[3][3] * v.w;
    return r;
  }
  constexpr Mat4 operator*(const Mat4& o) const {
    Mat4 r;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        r.m[i][j] =
            m[i][0] * o.m[0][j] + m[i][1] * o.m[1][j] + m[i][2] * o.m[2][j] + m[i][3] * o.m[3][j];
    return r;
  }
  // The homogeneous image of the point p (w = 1).
  constexpr Vec4 transformPoint(const Vec3& p) const { return *this * Vec4(p, 1); }

  // Column-major single precision, the layout of glUniformMatrix4fv with transpose = GL_FALSE.
  constexpr std::array<float, 16> columnMajorFloats() const {
    std::array<float, 16> r{};
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row) r[col * 4 + row] = static_cast<float>(m[row][col]);
    return r;
  }
};

}  // namespace penumbra
