#pragma once
// What the Galerkin solver's steps share (not part of its API).

#include <array>

#include "penumbra/radiosity/galerkin/galerkin_radiosity.h"

namespace penumbra {

struct GalerkinRadiosity::Counters {
  long long pointPairs = 0;
  long long visibilityRays = 0;
  long long unoccludedLinks = 0;
};

// A link's estimate: its coefficients and the oracle's figures.
struct GalerkinRadiosity::Estimate {
  std::array<double, 9> k{};
  double meanTransfer = 0;    // the mean point-pair transfer
  double spread = 0;          // max − min of the point-pair transfers
  double hiddenTransfer = 0;  // what the pairs found hidden would carry (weighted as the mean)
  Vec3 direction;             // unit, from the receiver's centre to the source's
};

}  // namespace penumbra
