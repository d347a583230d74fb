#pragma once
// Sorting integer keys without comparisons: the discontinuity mesh orders hundreds of thousands
// of packed edge-pair keys every frame, which a comparison sort took several percent of a large
// room's update to do.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace penumbra {

// Sorts the keys ascending and drops repeats: a least-significant-digit radix sort over the
// 16-bit digits that vary among them.
inline void sortUnique(std::vector<std::uint64_t>& keys) {
  // Keys made in order (most frames' lists) only have their repeats dropped.
  if (std::is_sorted(keys.begin(), keys.end())) {
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return;
  }
  std::uint64_t all = ~std::uint64_t(0), any = 0;
  for (const std::uint64_t key : keys) {
    all &= key;
    any |= key;
  }
  const std::uint64_t varying = all ^ any;
  std::vector<std::uint64_t> sorted(keys.size());
  std::vector<std::size_t> start(std::size_t(1) << 16);
  for (int shift = 0; shift < 64; shift += 16) {
    if (((varying >> shift) & 0xffffu) == 0) continue;
    std::fill(start.begin(), start.end(), 0);
    for (const std::uint64_t key : keys) ++start[(key >> shift) & 0xffffu];
    std::size_t sum = 0;
    for (std::size_t& s : start) sum += std::exchange(s, sum);
    for (const std::uint64_t key : keys) sorted[start[(key >> shift) & 0xffffu]++] = key;
    keys.swap(sorted);
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (i == 0 || keys[i] != keys[i - 1]) keys[kept++] = keys[i];
  keys.resize(kept);
}

}  // namespace penumbra
