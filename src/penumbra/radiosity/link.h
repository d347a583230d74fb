#pragma once
// Links of the hierarchy (Hanrahan, Salzman & Aupperle 1991; clusters: Sillion 1995, Smits et al.
// 1994). A link transports energy from its source node to its receiver node:
//   E_receiver += transfer * B_source  (E: irradiance averaged over the receiver's surfaces,
//                                       B: area-mean radiosity of the source),
// transfer = unoccludedTransfer * visibility, the receiver-to-source form factor estimate times the
// fraction of unoccluded rays. A refined link stays as a *passive* link with its estimates and its
// children (the line-space hierarchy of Drettakis & Sillion 1997 re-activates or re-refines such
// history when objects move); only active links transfer energy.

#include <cstdint>
#include <vector>

#include "penumbra/radiosity/cluster.h"

namespace penumbra {

struct Link {
  NodeRef receiver;
  NodeRef source;
  float unoccludedTransfer = 0;  // form factor (receiver to source), visibility ignored
  float visibility = 1;          // fraction of unoccluded rays in [0, 1]
  // How much the point-to-source form factor varies over the receiver (max − min at the
  // quadrature points); for links with a cluster end, the transfer itself (unknown variation).
  float transferSpread = 0;
  // How much the form factor from a point of the source to the receiver varies over the source
  // (max − min); for a cluster source, the transfer times A_receiver / A_source (unknown
  // variation). Gathering spreads B over the source evenly, which is exact only where B or this
  // is constant: the source oracle weighs it with the variation of B.
  float sourceSpread = 0;
  // For a cluster source: the share of the unoccluded transfer that comes from each of its root
  // elements (the solver's rootOrder_ over the cluster's range), summing to 1. Gathering takes
  // Σ share x B of those elements instead of the cluster's area-mean B: a table top facing the
  // ceiling sends the ceiling its own radiosity, not the mean with its dark underside and legs
  // (Sillion 1995's directional clusters, per element). Empty for an element source and for a
  // passive link (its estimate is re-done when it is re-activated).
  std::vector<float> sourceShares;
  int shaft = -1;  // index of its shaft in the solver's shafts, -1 when not stored
  bool active = true;
  std::vector<int> children;  // links replacing this one after refinement (passive links)

  double transfer() const { return double(unoccludedTransfer) * visibility; }
};

}  // namespace penumbra
