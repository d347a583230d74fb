#include "penumbra/base/sort_unique.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace penumbra {
namespace {

std::vector<std::uint64_t> reference(std::vector<std::uint64_t> keys) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

// Against a comparison sort: keys varying in every 16-bit digit, in some digits only (the
// passes skipped), all equal, one, none.
TEST(SortUnique, EqualsSortThenUnique) {
  std::mt19937_64 rng(3);
  const std::vector<std::uint64_t> masks = {~0ull, 0xffff0000ffffull, 0xff00000000000000ull,
                                            0x3ull};
  for (const std::uint64_t mask : masks) {
    std::vector<std::uint64_t> keys;
    for (int i = 0; i < 50000; ++i) keys.push_back((rng() & mask) | 0x0000100000000000ull);
    for (int i = 0; i < 1000; ++i) keys.push_back(keys[size_t(rng() % keys.size())]);  // repeats
    const std::vector<std::uint64_t> expected = reference(keys);
    sortUnique(keys);
    EXPECT_EQ(keys, expected) << "mask " << mask;
  }
  std::vector<std::uint64_t> same(100, 7);
  sortUnique(same);
  EXPECT_EQ(same, std::vector<std::uint64_t>{7});
  std::vector<std::uint64_t> none;
  sortUnique(none);
  EXPECT_TRUE(none.empty());
}

}  // namespace
}  // namespace penumbra
