#pragma once
// Clusters: the volume hierarchy above the polygons (Sillion 1995, "A unified hierarchical
// algorithm for global illumination with scattering volumes and object clusters"; Smits, Arvo &
// Greenberg 1994, "A clustering algorithm for radiosity in complex environments"). One root
// cluster holds the whole scene; a cluster's children are sub-clusters and root elements. Links
// may join clusters to clusters or to elements, so distant groups exchange energy through one
// link instead of one per pair of polygons.

#include <vector>

#include "penumbra/radiosity/element.h"

namespace penumbra {

// A node of the hierarchy: a cluster or an element (indices into the solver's arrays).
struct NodeRef {
  enum Kind : unsigned char { kCluster, kElement };
  Kind kind = kCluster;
  int index = 0;

  bool isCluster() const { return kind == kCluster; }
  bool isElement() const { return kind == kElement; }
  bool operator==(const NodeRef&) const = default;
};

// A cluster's place in the hierarchy, shared by the solvers (each keeps its radiometry beside it).
struct ClusterNode {
  Box3 bounds;
  double area = 0;                // total area of the element surfaces inside
  std::vector<NodeRef> children;  // sub-clusters and root elements
  int elementBegin = 0;           // root elements inside: rootOrder[begin, end)
  int elementEnd = 0;
};

struct Cluster : ClusterNode {
  NodeRadiometry radiometry;
};

}  // namespace penumbra
