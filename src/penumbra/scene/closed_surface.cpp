#include "penumbra/scene/closed_surface.h"

#include <algorithm>
#include <array>
#include <numeric>

namespace penumbra {

namespace {

int root(std::vector<int>& parent, int i) {
  while (parent[size_t(i)] != i) {
    parent[size_t(i)] = parent[size_t(parent[size_t(i)])];
    i = parent[size_t(i)];
  }
  return i;
}

}  // namespace

std::vector<int> closedSurfaces(const std::vector<const Polygon3*>& polygons) {
  // Every edge under its undirected key (its ends in coordinate order), with its direction and
  // polygon; sorted, each key's run is the polygons that share that edge.
  struct Edge {
    std::array<double, 6> key;
    bool forward;
    int polygon;
  };
  std::vector<Edge> edges;
  std::vector<char> open(polygons.size(), 1);  // until it has an edge
  for (size_t p = 0; p < polygons.size(); ++p) {
    const Polygon3& ring = *polygons[p];
    for (size_t i = 0; i < ring.size(); ++i) {
      const Vec3& a = ring[i];
      const Vec3& b = ring[(i + 1) % ring.size()];
      if (a == b) continue;
      open[p] = 0;
      const std::array<double, 3> u{a.x, a.y, a.z}, v{b.x, b.y, b.z};
      const bool forward = u < v;
      const std::array<double, 3>& lo = forward ? u : v;
      const std::array<double, 3>& hi = forward ? v : u;
      edges.push_back({{lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]}, forward, int(p)});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.key < y.key; });
  std::vector<int> parent(polygons.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (size_t i = 0; i < edges.size();) {
    size_t end = i + 1;
    while (end < edges.size() && edges[end].key == edges[i].key) ++end;
    // Closed along this edge: exactly two uses, one each way.
    const bool closed = end - i == 2 && edges[i].forward != edges[i + 1].forward;
    for (size_t k = i; k < end; ++k) {
      if (!closed) open[size_t(edges[k].polygon)] = 1;
      const int a = root(parent, edges[i].polygon), b = root(parent, edges[k].polygon);
      if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
    }
    i = end;
  }
  // A set is open where any of its polygons is.
  std::vector<char> openRoot(polygons.size(), 0);
  for (size_t p = 0; p < polygons.size(); ++p)
    if (open[p]) openRoot[size_t(root(parent, int(p)))] = 1;
  std::vector<int> surface(polygons.size(), -1), numberOfRoot(polygons.size(), -1);
  int surfaces = 0;
  for (size_t p = 0; p < polygons.size(); ++p) {
    const int r = root(parent, int(p));
    if (openRoot[size_t(r)]) continue;
    if (numberOfRoot[size_t(r)] < 0) numberOfRoot[size_t(r)] = surfaces++;
    surface[p] = numberOfRoot[size_t(r)];
  }
  return surface;
}

}  // namespace penumbra
