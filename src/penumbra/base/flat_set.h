#pragma once
// A set of small keys in one array (open addressing, linear probing): no allocation per key. The
// discontinuity mesh's per-frame enumerations insert about a million keys each frame (EEE
// candidates, seen once per cut); with std::unordered_set's node per key, allocating and freeing
// them was a third of an update's time in a 10,000-polygon room.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penumbra {

// Hash: a function object giving a std::uint64_t for a Key (mixed further here, so a plain
// combination of the key's words will do).
template <class Key, class Hash>
class FlatSet {
 public:
  // Room for `expected` keys without growing.
  explicit FlatSet(std::size_t expected = 0) { rehash(capacityFor(expected)); }

  // Inserts the key; false when it was there already.
  bool insert(const Key& key) {
    if (2 * (size_ + 1) > slots_.size()) rehash(2 * slots_.size());
    return insertInto(slots_, key);
  }
  bool contains(const Key& key) const {
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = slotOf(key, mask);; i = (i + 1) & mask) {
      if (!slots_[i].used) return false;
      if (slots_[i].key == key) return true;
    }
  }
  std::size_t size() const { return size_; }
  void clear() {
    for (Slot& slot : slots_) slot.used = false;
    size_ = 0;
  }

 private:
  struct Slot {
    Key key{};
    bool used = false;
  };
  static std::size_t capacityFor(std::size_t expected) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected) capacity *= 2;
    return capacity;
  }
  static std::size_t slotOf(const Key& key, std::size_t mask) {
    std::uint64_t z = std::uint64_t(Hash()(key)) + 0x9e3779b97f4a7c15ull;  // SplitMix64's finalizer
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return std::size_t(z ^ (z >> 31)) & mask;
  }
  bool insertInto(std::vector<Slot>& slots, const Key& key) {
    const std::size_t mask = slots.size() - 1;
    for (std::size_t i = slotOf(key, mask);; i = (i + 1) & mask) {
      if (!slots[i].used) {
        slots[i] = {key, true};
        ++size_;
        return true;
      }
      if (slots[i].key == key) return false;
    }
  }
  void rehash(std::size_t capacity) {
    std::vector<Slot> old = std::move(slots_);
    slots_.assign(capacity, Slot{});
    size_ = 0;
    for (const Slot& slot : old)
      if (slot.used) insertInto(slots_, slot.key);
  }

  std::vector<Slot> slots_;
  std::size_t size_ = 0;
};

// For keys that are one integer.
struct IdentityHash {
  std::uint64_t operator()(std::uint64_t key) const { return key; }
};

}  // namespace penumbra
