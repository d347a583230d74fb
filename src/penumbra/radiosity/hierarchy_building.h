#pragma once
// The hierarchy both radiosity solvers start from: element quadtree roots from the input polygons
// (Hanrahan, Salzman & Aupperle 1991) and the volume cluster hierarchy above them (Sillion 1995;
// Smits, Arvo & Greenberg 1994).

#include <vector>

#include "penumbra/radiosity/cluster.h"
#include "penumbra/scene/posed_scene.h"

namespace penumbra {

// The root elements of every polygon with area: the polygon itself when it is a triangle or a
// convex quadrilateral, its triangulation otherwise; each with the polygon's reflectance and
// emission (radiometry.emission). `polygonRoots[p]` receives the indices of polygon p's roots.
std::vector<Element> rootElements(const PosedScene& scene,
                                  std::vector<std::vector<int>>& polygonRoots);
// The root elements of one polygon (what rootElements gives for it), in the same order: a moved
// polygon's roots are remade with this, bit for bit as a fresh build makes them.
std::vector<Element> rootElementsOf(const PosedScene& scene, const WorldPolygon& polygon);

struct ClusterHierarchy {
  std::vector<ClusterNode> clusters;  // [0] is the root
  std::vector<int> rootOrder;         // root elements in cluster order
};
// Octree clusters over the root elements: the box of the element centroids cut into octants
// recursively; an octant with one element contributes that element directly.
ClusterHierarchy buildClusterHierarchy(const std::vector<Element>& roots);
// A hierarchy that can move: the root cluster's children are one subtree per group of root
// elements (the static scene, then each moving object), so a moving object's elements stay
// together under one node and the static clusters never change. Each subtree is cut by the
// octants of `keys` (one point per root element): for a moving object, points in its own
// coordinates, so its subtree has the same shape at every pose. Empty groups are skipped; a
// group of one element hangs from the root directly.
ClusterHierarchy buildClusterHierarchy(const std::vector<Element>& roots,
                                       const std::vector<std::vector<int>>& groups,
                                       const std::vector<Vec3>& keys);

}  // namespace penumbra
