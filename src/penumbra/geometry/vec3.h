#pragma once
// 3D vectors and points in double precision (world units are metres by convention).

#include <cmath>
#include <ostream>

namespace penumbra {

struct Vec3 {
  double x = 0, y = 0, z = 0;

  constexpr Vec3() = default;
  constexpr Vec3(double vx, double vy, double vz) : x(vx), y(vy), z(vz) {}

  constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
  constexpr Vec3& operator+=(const Vec3& o) { return *this = *this + o; }
  constexpr Vec3& operator-=(const Vec3& o) { return *this = *this - o; }
  constexpr Vec3& operator*=(double s) { return *this = *this * s; }
  constexpr bool operator==(const Vec3&) const = default;

  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

  bool isFinite() const { return std::isfinite(x) && std::isfinite(y) && std::isfinite(z); }
};

constexpr Vec3 operator*(double s, const Vec3& v) { return v * s; }
constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr double squaredLength(const Vec3& v) { return dot(v, v); }
inline double length(const Vec3& v) { return std::sqrt(dot(v, v)); }
inline double distance(const Vec3& a, const Vec3& b) { return length(a - b); }
// Precondition: v is not the zero vector.
inline Vec3 normalize(const Vec3& v) { return v / length(v); }
constexpr Vec3 componentMin(const Vec3& a, const Vec3& b) {
  return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z};
}
constexpr Vec3 componentMax(const Vec3& a, const Vec3& b) {
  return {a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z};
}
constexpr Vec3 lerp(const Vec3& a, const Vec3& b, double t) { return a + (b - a) * t; }
// Index (0, 1, 2) of the component with the largest magnitude.
inline int dominantAxis(const Vec3& v) {
  const double ax = std::abs(v.x), ay = std::abs(v.y), az = std::abs(v.z);
  return ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
}

inline std::ostream& operator<<(std::ostream& out, const Vec3& v) {
  return out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
}

struct Vec2 {
  double x = 0, y = 0;

  constexpr Vec2() = default;
  constexpr Vec2(double vx, double vy) : x(vx), y(vy) {}
  constexpr Vec2 operator+(const Vec2& o) const { return {x + o.x, y + o.y}; }
  constexpr Vec2 operator-(const Vec2& o) const { return {x - o.x, y - o.y}; }
  constexpr Vec2 operator*(double s) const { return {x * s, y * s}; }
  constexpr bool operator==(const Vec2&) const = default;
};

constexpr double dot(const Vec2& a, const Vec2& b) { return a.x * b.x + a.y * b.y; }
constexpr double cross(const Vec2& a, const Vec2& b) { return a.x * b.y - a.y * b.x; }

}  // namespace penumbra
