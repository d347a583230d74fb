#include "penumbra/base/key_counts.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <random>

namespace penumbra {
namespace {

// Against a std::map of counts over a random walk of adds and removes (of counted keys), through
// growths and rebuilds that drop keys at zero: add and remove report the 0/1 transitions exactly
// when the reference does, and counts agree after, for every key ever used.
TEST(KeyCounts, AgreesWithAMapOfCountsThroughGrowthAndRebuilds) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::uint64_t> pick(0, 3000);
  KeyCounts counts;
  std::map<std::uint64_t, std::uint32_t> reference;
  for (int i = 0; i < 60000; ++i) {
    const std::uint64_t key = pick(rng) * 0x10001ull;  // spread over the high bits too
    std::uint32_t& expected = reference[key];
    if (expected > 0 && rng() % 2 == 0) {
      EXPECT_EQ(counts.remove(key), expected == 1) << "key " << key;
      --expected;
    } else {
      EXPECT_EQ(counts.add(key), expected == 0) << "key " << key;
      ++expected;
    }
  }
  std::size_t counted = 0;
  for (const auto& [key, expected] : reference) {
    EXPECT_EQ(counts.count(key), expected) << "key " << key;
    counted += expected > 0 ? 1 : 0;
  }
  EXPECT_EQ(counts.size(), counted);
  EXPECT_EQ(counts.count(0x123456789ull), 0u);
  EXPECT_FALSE(counts.remove(0x123456789ull));  // never counted
}

TEST(KeyCounts, AKeyCountedAgainAfterFallingToZero) {
  KeyCounts counts;
  EXPECT_TRUE(counts.add(42));
  EXPECT_FALSE(counts.add(42));
  EXPECT_FALSE(counts.remove(42));
  EXPECT_TRUE(counts.remove(42));
  EXPECT_EQ(counts.size(), 0u);
  EXPECT_TRUE(counts.add(42));
  EXPECT_EQ(counts.count(42), 1u);
}

}  // namespace
}  // namespace penumbra
