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

struct ClusterHierarchy {
  std::vector<ClusterNode> clusters;  // [0] is the root
  std::vector<int> rootOrder;         // root elements in cluster order
};
// Octree clusters over the root elements: the box of the element centroids cut into octants
// recursively; an octant with one element contributes that element directly.
ClusterHierarchy buildClusterHierarchy(const std::vector<Element>& roots);

}  // namespace penumbra
