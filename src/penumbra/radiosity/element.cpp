#include "penumbra/radiosity/element.h"

#include <algorithm>
#include <limits>

#include "penumbra/geometry/polygon.h"

namespace penumbra {

namespace {
Vec3 uniformInTriangle(const Vec3& a, const Vec3& b, const Vec3& c, double u, double v) {
  // Folding the unit square onto the triangle keeps the density uniform.
  if (u + v > 1) u = 1 - u, v = 1 - v;
  return a + (b - a) * u + (c - a) * v;
}
}  // namespace

double elementArea(const std::array<Vec3, 4>& v, int count) {
  double a = triangleArea(v[0], v[1], v[2]);
  if (count == 4) a += triangleArea(v[0], v[2], v[3]);
  return a;
}

Box3 ElementShape::bounds() const {
  Box3 b;
  for (int i = 0; i < vertexCount; ++i) b.extend(vertices[i]);
  return b;
}

Vec3 ElementShape::centroid() const {
  if (vertexCount == 3) return (vertices[0] + vertices[1] + vertices[2]) / 3.0;
  const double a0 = triangleArea(vertices[0], vertices[1], vertices[2]);
  const double a1 = triangleArea(vertices[0], vertices[2], vertices[3]);
  const Vec3 c0 = (vertices[0] + vertices[1] + vertices[2]) / 3.0;
  const Vec3 c1 = (vertices[0] + vertices[2] + vertices[3]) / 3.0;
  return a0 + a1 > 0 ? (c0 * a0 + c1 * a1) / (a0 + a1) : c0;
}

std::array<std::array<Vec3, 4>, 16> ElementShape::grandchildCells() const {
  std::array<std::array<Vec3, 4>, 16> cells{};
  int k = 0;
  for (const auto& loop : childVertices()) {
    ElementShape child;
    child.vertices = loop;
    child.vertexCount = vertexCount;
    for (const auto& subLoop : child.childVertices()) cells[k++] = subLoop;
  }
  return cells;
}

std::array<Vec3, 16> ElementShape::grandchildCentres() const {
  std::array<Vec3, 16> centres{};
  const auto cells = grandchildCells();
  for (int k = 0; k < 16; ++k) {
    Vec3 x{0, 0, 0};
    for (int i = 0; i < vertexCount; ++i) x += cells[k][i];
    centres[k] = x / double(vertexCount);
  }
  return centres;
}

std::array<std::array<Vec3, 4>, 4> ElementShape::childVertices() const {
  const auto& v = vertices;
  std::array<std::array<Vec3, 4>, 4> c{};
  if (vertexCount == 3) {
    const Vec3 m01 = (v[0] + v[1]) * 0.5, m12 = (v[1] + v[2]) * 0.5, m20 = (v[2] + v[0]) * 0.5;
    c[0] = {v[0], m01, m20, {}};
    c[1] = {m01, v[1], m12, {}};
    c[2] = {m20, m12, v[2], {}};
    c[3] = {m01, m12, m20, {}};
  } else {
    const Vec3 m01 = (v[0] + v[1]) * 0.5, m12 = (v[1] + v[2]) * 0.5, m23 = (v[2] + v[3]) * 0.5,
               m30 = (v[3] + v[0]) * 0.5;
    const Vec3 mid = (m01 + m23) * 0.5;
    c[0] = {v[0], m01, mid, m30};
    c[1] = {m01, v[1], m12, mid};
    c[2] = {mid, m12, v[2], m23};
    c[3] = {m30, mid, m23, v[3]};
  }
  return c;
}

Vec3 ElementShape::samplePoint(double u, double v) const {
  if (vertexCount == 3) return uniformInTriangle(vertices[0], vertices[1], vertices[2], u, v);
  const double a0 = triangleArea(vertices[0], vertices[1], vertices[2]);
  const double a1 = triangleArea(vertices[0], vertices[2], vertices[3]);
  const double split = a0 / std::max(a0 + a1, std::numeric_limits<double>::min());
  if (u < split) return uniformInTriangle(vertices[0], vertices[1], vertices[2], u / split, v);
  return uniformInTriangle(vertices[0], vertices[2], vertices[3], (u - split) / (1 - split), v);
}

int ElementShape::childContaining(const Vec3& p) const {
  const auto& v = vertices;
  // Is p on the same side of the line (a, b) as q?
  const auto sameSide = [&](const Vec3& a, const Vec3& b, const Vec3& q) {
    const Vec3 edge = b - a;
    return dot(cross(edge, p - a), normal) * dot(cross(edge, q - a), normal) >= 0;
  };
  if (vertexCount == 3) {
    const Vec3 m01 = (v[0] + v[1]) * 0.5, m12 = (v[1] + v[2]) * 0.5, m20 = (v[2] + v[0]) * 0.5;
    if (sameSide(m01, m20, v[0])) return 0;
    if (sameSide(m01, m12, v[1])) return 1;
    if (sameSide(m20, m12, v[2])) return 2;
    return 3;
  }
  const Vec3 m01 = (v[0] + v[1]) * 0.5, m12 = (v[1] + v[2]) * 0.5, m23 = (v[2] + v[3]) * 0.5,
             m30 = (v[3] + v[0]) * 0.5;
  const bool nearV0V1 = sameSide(m30, m12, v[0]);  // children 0 and 1
  const bool nearV0V3 = sameSide(m01, m23, v[0]);  // children 0 and 3
  return nearV0V1 ? (nearV0V3 ? 0 : 1) : (nearV0V3 ? 3 : 2);
}

int ElementShape::grandchildContaining(const Vec3& p) const {
  const int c = childContaining(p);
  ElementShape child;
  child.vertices = childVertices()[c];
  child.vertexCount = vertexCount;
  child.normal = normal;
  return 4 * c + child.childContaining(p);
}

double ElementShape::insideness(const Vec3& p) const {
  double smallest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < vertexCount; ++i) {
    const Vec3& a = vertices[i];
    const Vec3& b = vertices[(i + 1) % vertexCount];
    const Vec3 inward = cross(normal, b - a);
    const double len = length(inward);
    if (len == 0) continue;
    smallest = std::min(smallest, dot(p - a, inward) / len);
  }
  return smallest;
}

}  // namespace penumbra
