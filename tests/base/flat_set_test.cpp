#include "penumbra/base/flat_set.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>
#include <set>

namespace penumbra {
namespace {

// Against std::set on the same random keys (many repeated), through several growths: insert says
// whether a key is new exactly when the reference set does, and membership agrees after.
TEST(FlatSet, AgreesWithStdSetThroughGrowth) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<std::uint64_t> key(0, 5000);
  FlatSet<std::uint64_t, IdentityHash> flat;
  std::set<std::uint64_t> reference;
  for (int i = 0; i < 20000; ++i) {
    const std::uint64_t k = key(rng);
    EXPECT_EQ(flat.insert(k), reference.insert(k).second) << "key " << k;
  }
  EXPECT_EQ(flat.size(), reference.size());
  for (std::uint64_t k = 0; k <= 5000; ++k) EXPECT_EQ(flat.contains(k), reference.count(k) == 1);
  flat.clear();
  EXPECT_EQ(flat.size(), 0u);
  EXPECT_FALSE(flat.contains(*reference.begin()));
  EXPECT_TRUE(flat.insert(*reference.begin()));
}

// Keys that collide in the hash before mixing (all multiples of a large power of two) and keys of
// several words: still told apart.
TEST(FlatSet, TellsApartKeysWhoseHashesCollide) {
  struct Weak {
    std::uint64_t operator()(const std::array<int, 3>& k) const { return std::uint64_t(k[0]); }
  };
  FlatSet<std::array<int, 3>, Weak> triples;
  for (int b = 0; b < 50; ++b)
    for (int c = 0; c < 50; ++c) EXPECT_TRUE(triples.insert({7, b, c}));
  for (int b = 0; b < 50; ++b)
    for (int c = 0; c < 50; ++c) EXPECT_FALSE(triples.insert({7, b, c}));
  EXPECT_EQ(triples.size(), 2500u);
  FlatSet<std::uint64_t, IdentityHash> spread(4);
  for (std::uint64_t i = 0; i < 1000; ++i) EXPECT_TRUE(spread.insert(i << 40));
  for (std::uint64_t i = 0; i < 1000; ++i) EXPECT_TRUE(spread.contains(i << 40));
  EXPECT_FALSE(spread.contains(1));
}

}  // namespace
}  // namespace penumbra
