#pragma once
// Hashing keys made of doubles, as == compares them (zeros of either sign alike). std::hash<double>
// runs a byte-wise Murmur hash per value: the engine hashes twelve to eighteen doubles per surface
// and per EEE trace, for every surface of the frame before and of this one (a million keys a step
// in a 10,000-polygon room), where it was 4% of the update step.

#include <bit>
#include <cstdint>

namespace penumbra {

// Folds the bits of x into h (SplitMix64's finaliser over their sum).
inline std::uint64_t hashCombine(std::uint64_t h, double x) {
  std::uint64_t z = h + (x == 0 ? 0 : std::bit_cast<std::uint64_t>(x)) + 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

}  // namespace penumbra
