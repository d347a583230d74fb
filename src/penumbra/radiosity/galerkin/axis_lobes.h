#pragma once
// Directional radiometry of a cluster on the six axis directions (+x, −x, +y, −y, +z, −z): what a
// cluster of surfaces sends and receives depends on which way its surfaces face. An isotropic
// cluster (the mean of max(0, cos θ) over directions, 1/4, for every surface) sends half of a
// floor's light downwards, where nothing receives it: 3-5% of the energy lost per bounce in the
// chair room under its lamp. On the lobes a surface facing an axis is exact, and a tilted one
// is shared between the axes its normal leans to (Σ_k |n_k| normalised, so energy is kept).

#include <array>
#include <cmath>

#include "penumbra/base/rgb.h"
#include "penumbra/geometry/vec3.h"

namespace penumbra {

// Lobe 2k is the +axis k, lobe 2k + 1 the −axis k.
using AxisLobes = std::array<Rgb, 6>;

// How a surface of unit normal n shares its exitance among the lobes (summing to 1).
inline std::array<double, 6> exitanceShares(const Vec3& n) {
  const double sum = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
  std::array<double, 6> shares{};
  for (int k = 0; k < 3; ++k) {
    shares[2 * k] = n[k] > 0 ? n[k] / sum : 0;
    shares[2 * k + 1] = n[k] < 0 ? -n[k] / sum : 0;
  }
  return shares;
}

// The power per unit projected solid angle (B A cos for one surface) the lobes send in the unit
// direction w: Σ_k |w_k| lobe(k, sign w_k). Exact for a surface facing an axis.
inline Rgb exitanceToward(const AxisLobes& lobes, const Vec3& w) {
  Rgb sum;
  for (int k = 0; k < 3; ++k) sum += lobes[2 * k + (w[k] < 0 ? 1 : 0)] * std::abs(w[k]);
  return sum;
}

// Flux density `flux` arriving from the unit direction u (pointing towards its source): a
// surface facing u receives all of it, one facing an axis |u_k| of it.
inline void addArriving(AxisLobes& lobes, const Rgb& flux, const Vec3& u) {
  for (int k = 0; k < 3; ++k) lobes[2 * k + (u[k] < 0 ? 1 : 0)] += flux * std::abs(u[k]);
}

// How a link meets a cluster end's lobes: per lobe, the weight of that lobe in the light the
// cluster sends towards the link's other end, or in how the light arriving from it spreads over
// the cluster's lobes. One direction u gives |u_k| on the lobe of u_k's sign (exact for a
// surface facing an axis); a link weighs the directions of its point pairs by what each carries
// (GalerkinRadiosity::estimate), so that a source seen over a wide angle (a floor under a chair)
// is not taken along the one direction between the ends' centres.
using LobeWeights = std::array<float, 6>;

inline LobeWeights lobeWeightsOf(const Vec3& u) {
  LobeWeights weights{};
  for (int k = 0; k < 3; ++k) weights[2 * k + (u[k] < 0 ? 1 : 0)] = float(std::abs(u[k]));
  return weights;
}

// The weights of the opposite directions (each +axis lobe's with its −axis lobe's): a link's
// weights are taken from its receiver towards its source, and its source sends the other way.
inline LobeWeights opposite(const LobeWeights& weights) {
  LobeWeights flipped{};
  for (int k = 0; k < 3; ++k) {
    flipped[2 * k] = weights[2 * k + 1];
    flipped[2 * k + 1] = weights[2 * k];
  }
  return flipped;
}

// What the lobes send with these weights (exitanceToward of each direction, weighed).
inline Rgb exitanceToward(const AxisLobes& lobes, const LobeWeights& weights) {
  Rgb sum;
  for (int f = 0; f < 6; ++f) sum += lobes[f] * double(weights[f]);
  return sum;
}

// Flux density `flux` arriving over a link whose directions these weights describe.
inline void addArriving(AxisLobes& lobes, const Rgb& flux, const LobeWeights& weights) {
  for (int f = 0; f < 6; ++f) lobes[f] += flux * double(weights[f]);
}

// The irradiance on a surface of unit normal n from what arrived on the lobes.
inline Rgb irradianceOn(const AxisLobes& lobes, const Vec3& n) {
  Rgb sum;
  for (int k = 0; k < 3; ++k) sum += lobes[2 * k + (n[k] < 0 ? 1 : 0)] * std::abs(n[k]);
  return sum;
}

}  // namespace penumbra
