// The hierarchy: element quadtree roots from the input polygons (Hanrahan, Salzman & Aupperle
// 1991) and the volume cluster hierarchy above them (Sillion 1995; Smits, Arvo & Greenberg 1994).

#include "penumbra/radiosity/hierarchy_building.h"

#include <algorithm>

#include "penumbra/geometry/triangulation.h"

namespace penumbra {

namespace {

constexpr int kMaxElementsPerLeafCluster = 4;
constexpr int kMaxClusterDepth = 24;

bool isConvexQuad(const Polygon3& q, const Vec3& normal) {
  for (int i = 0; i < 4; ++i)
    if (dot(cross(q[(i + 1) % 4] - q[i], q[(i + 2) % 4] - q[(i + 1) % 4]), normal) <= 0)
      return false;
  return true;
}

}  // namespace

std::vector<Element> rootElementsOf(const PosedScene& scene, const WorldPolygon& polygon) {
  std::vector<Element> elements;
  const Material& material = scene.materialOf(polygon);
  const Polygon3 loop = withoutRepeatedVertices(polygon.vertices);
  if (loop.size() < 3 || polygon.area <= 0) return elements;
  std::vector<std::array<Vec3, 4>> pieces;
  std::vector<int> counts;
  if (loop.size() == 3 || (loop.size() == 4 && isConvexQuad(loop, polygon.plane.normal))) {
    std::array<Vec3, 4> v{};
    std::copy(loop.begin(), loop.end(), v.begin());
    pieces.push_back(v);
    counts.push_back(int(loop.size()));
  } else {
    for (const auto& t : triangulate(loop)) {
      pieces.push_back({loop[t[0]], loop[t[1]], loop[t[2]], {}});
      counts.push_back(3);
    }
  }
  for (size_t k = 0; k < pieces.size(); ++k) {
    Element e;
    e.vertices = pieces[k];
    e.vertexCount = std::uint8_t(counts[k]);
    e.polygon = polygon.id;
    e.normal = polygon.plane.normal;
    e.area = elementArea(e.vertices, e.vertexCount);
    if (e.area <= 0) continue;
    e.reflectance = material.reflectance;
    e.radiometry.emission = material.emission;
    elements.push_back(e);
  }
  return elements;
}

std::vector<Element> rootElements(const PosedScene& scene,
                                  std::vector<std::vector<int>>& polygonRoots) {
  std::vector<Element> elements;
  polygonRoots.assign(scene.polygons.size(), {});
  for (const WorldPolygon& polygon : scene.polygons)
    for (Element& e : rootElementsOf(scene, polygon)) {
      polygonRoots[polygon.id].push_back(int(elements.size()));
      elements.push_back(std::move(e));
    }
  return elements;
}

namespace {

// Volume clustering (Sillion 1995): the box of the element centroids is cut into octants
// recursively; an octant with one element contributes that element directly.
struct ClusterBuilder {
  const std::vector<Element>& elements;
  const std::vector<Vec3>& keys;  // where each element sits, for the octants
  ClusterHierarchy& out;
  int build(int begin, int end, int depth);
};

int ClusterBuilder::build(int begin, int end, int depth) {
  std::vector<ClusterNode>& clusters = out.clusters;
  std::vector<int>& order = out.rootOrder;
  const int index = int(clusters.size());
  clusters.emplace_back();
  ClusterNode cluster;
  cluster.elementBegin = begin;
  cluster.elementEnd = end;
  Box3 centroids;
  for (int i = begin; i < end; ++i) {
    const Element& e = elements[order[i]];
    cluster.bounds.extend(e.bounds());
    centroids.extend(keys[order[i]]);
  }
  const bool isSmall = end - begin <= kMaxElementsPerLeafCluster || depth >= kMaxClusterDepth ||
                       centroids.diagonalLength() == 0;
  if (isSmall) {
    for (int i = begin; i < end; ++i) cluster.children.push_back({NodeRef::kElement, order[i]});
  } else {
    const Vec3 mid = centroids.center();
    const auto octant = [&](int element) {
      const Vec3& c = keys[element];
      return (c.x > mid.x ? 1 : 0) | (c.y > mid.y ? 2 : 0) | (c.z > mid.z ? 4 : 0);
    };
    std::stable_sort(order.begin() + begin, order.begin() + end,
                     [&](int a, int b) { return octant(a) < octant(b); });
    int first = begin;
    while (first < end) {
      int last = first + 1;
      while (last < end && octant(order[last]) == octant(order[first])) ++last;
      if (last - first == 1)
        cluster.children.push_back({NodeRef::kElement, order[first]});
      else if (first == begin && last == end)  // one octant holds all: stop here
        for (int i = begin; i < end; ++i) cluster.children.push_back({NodeRef::kElement, order[i]});
      else
        cluster.children.push_back({NodeRef::kCluster, build(first, last, depth + 1)});
      first = last;
    }
  }
  // Summed in the final order of the range (the octant sort above reorders it), which is how a
  // moving hierarchy sums it again after a move: equal areas mean equal bits.
  for (int i = begin; i < end; ++i) cluster.area += elements[order[i]].area;
  clusters[index] = std::move(cluster);
  return index;
}

}  // namespace

ClusterHierarchy buildClusterHierarchy(const std::vector<Element>& roots) {
  ClusterHierarchy hierarchy;
  hierarchy.rootOrder.resize(roots.size());
  for (size_t i = 0; i < roots.size(); ++i) hierarchy.rootOrder[i] = int(i);
  hierarchy.clusters.reserve(roots.size());
  std::vector<Vec3> centroids(roots.size());
  for (size_t i = 0; i < roots.size(); ++i) centroids[i] = roots[i].centroid();
  ClusterBuilder{roots, centroids, hierarchy}.build(0, int(roots.size()), 0);
  return hierarchy;
}

ClusterHierarchy buildClusterHierarchy(const std::vector<Element>& roots,
                                       const std::vector<std::vector<int>>& groups,
                                       const std::vector<Vec3>& keys) {
  ClusterHierarchy hierarchy;
  for (const std::vector<int>& group : groups)
    hierarchy.rootOrder.insert(hierarchy.rootOrder.end(), group.begin(), group.end());
  hierarchy.clusters.reserve(roots.size() + 1);
  hierarchy.clusters.emplace_back();
  ClusterNode root;
  root.elementEnd = int(hierarchy.rootOrder.size());
  ClusterBuilder builder{roots, keys, hierarchy};
  int begin = 0;
  for (const std::vector<int>& group : groups) {
    const int end = begin + int(group.size());
    if (end - begin == 1)
      root.children.push_back({NodeRef::kElement, hierarchy.rootOrder[begin]});
    else if (end > begin)
      root.children.push_back({NodeRef::kCluster, builder.build(begin, end, 1)});
    begin = end;
  }
  for (int element : hierarchy.rootOrder) {
    root.bounds.extend(roots[element].bounds());
    root.area += roots[element].area;
  }
  hierarchy.clusters[0] = std::move(root);
  return hierarchy;
}

}  // namespace penumbra
