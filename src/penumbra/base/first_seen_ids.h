#pragma once
// Ids by key, numbered in the order keys are first seen, in one array (open addressing, linear
// probing): no allocation per key. For indexes built again every frame by the hundred thousand
// (the discontinuity mesh's edge adjacency, its EEE candidates by crossing), where a tree of a
// node per key cost more than the work it indexed.

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace penumbra {

// Key: a std::array of integers (its words are hashed).
template <class Key>
class FirstSeenIds {
 public:
  FirstSeenIds() : FirstSeenIds(0) {}
  explicit FirstSeenIds(std::size_t expected) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected) capacity *= 2;
    slots_.assign(capacity, Slot{});
  }
  // The key's id, and whether it is new (then `next`, which the caller counts on).
  std::pair<int, bool> idOf(const Key& key, int next) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = slotOf(key, mask);; i = (i + 1) & mask) {
      if (slots_[i].id < 0) {
        slots_[i] = {key, next};
        ++size_;
        return {next, true};
      }
      if (slots_[i].key == key) return {slots_[i].id, false};
    }
  }
  // The key's id, or -1.
  int find(const Key& key) const {
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = slotOf(key, mask); slots_[i].id >= 0; i = (i + 1) & mask)
      if (slots_[i].key == key) return slots_[i].id;
    return -1;
  }
  std::size_t size() const { return size_; }
  std::size_t memoryBytes() const { return slots_.capacity() * sizeof(Slot); }

 private:
  struct Slot {
    Key key{};
    int id = -1;
  };
  static std::size_t slotOf(const Key& key, std::size_t mask) {
    std::uint64_t h = 0;
    for (const auto word : key) {
      std::uint64_t z = (h ^ std::uint64_t(word)) + 0x9e3779b97f4a7c15ull;  // SplitMix64
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
      h = z ^ (z >> 31);
    }
    return std::size_t(h) & mask;
  }
  void grow() {
    std::vector<Slot> old = std::move(slots_);
    slots_.assign(2 * old.size(), Slot{});
    const std::size_t mask = slots_.size() - 1;
    for (const Slot& slot : old) {
      if (slot.id < 0) continue;
      std::size_t i = slotOf(slot.key, mask);
      while (slots_[i].id >= 0) i = (i + 1) & mask;
      slots_[i] = slot;
    }
  }
  std::vector<Slot> slots_;
  std::size_t size_ = 0;
};

}  // namespace penumbra
