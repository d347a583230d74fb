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
  float visibility = 1;          // visible fraction of the transfer in [0, 1]
  // How much the point-to-source form factor varies over the receiver (max − min at the
  // quadrature points); for links with a cluster end, the transfer itself (unknown variation).
  float transferSpread = 0;
  // How much the form factor from a point of the source to the receiver varies over the source
  // (max − min); for a cluster source, the transfer times A_receiver / A_source (unknown
  // variation). Gathering spreads B over the source evenly, which is exact only where B or this
  // is constant: the source oracle weighs it with the variation of B.
  float sourceSpread = 0;
  // Where the transfer comes from on the source, summing to 1. For a cluster source: the share
  // of the unoccluded transfer from each of its root elements (the solver's rootOrder_ over the
  // cluster's range); gathering takes Σ share x B of those elements instead of the cluster's
  // area-mean B, so a table top facing the ceiling sends the ceiling its own radiosity, not the
  // mean with its dark underside and legs (Sillion 1995's directional clusters, per element).
  // For an element source (with RadiosityOptions::elementSourceShares): the share of the visible
  // transfer that lands on each of its sixteen grandchildren (quadtree cells two levels down), from
  // the visibility rays' ends with the weights of the link's visibility estimate (so the shares
  // split that estimate, nothing else); once the source is split, gathering takes Σ share x B of
  // those cells (of the children while they are leaves): the part of a wall hidden behind a sofa
  // from a receiver is also the part in the sofa's shadow, dark, and the mean B of the wall would
  // send its dark part's light at the bright part's visibility. Empty for a contact link, when
  // nothing is visible, and for a passive link (its estimate is re-done when it is re-activated).
  std::vector<float> sourceShares;
  // With RadiosityOptions::exactVisibility, for an element-to-element link whose shaft holds
  // occluders: the exact visible form factor at each of the receiver's 16 grandchild centres
  // (0 where a polygon in contact covers the point). The receiver oracle uses them as they are,
  // so it sees how visibility varies over the receiver. Empty otherwise and for passive links.
  std::vector<float> pointVisibleTransfers;
  int shaft = -1;  // index of its shaft in the solver's shafts, -1 when not stored
  bool active = true;
  std::vector<int> children;  // links replacing this one after refinement (passive links)

  double transfer() const { return double(unoccludedTransfer) * visibility; }
};

}  // namespace penumbra
