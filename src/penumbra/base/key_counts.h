#pragma once
// Reference counts of 64-bit keys in one array (open addressing, linear probing): the
// discontinuity mesh's EEE candidates are counted by the cuts that list them, so an update adds
// and removes the candidates of the cuts that changed instead of listing every cut again. A key
// whose count falls to zero keeps its slot (a later add finds it) until the table is rebuilt.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penumbra {

class KeyCounts {
 public:
  // Counts the key once more; true when it was not counted before (0 to 1).
  bool add(std::uint64_t key) {
    // Slots in use, zero counts included, stay under half: probes stay short.
    if (2 * (used_ + 1) > slots_.size()) rehash();
    Slot& slot = slots_[find(key)];
    if (!slot.used) {
      slot = {key, 0, true};
      ++used_;
    }
    if (slot.count++ == 0) ++counted_;
    return slot.count == 1;
  }
  // Counts the key once less; true when it is no longer counted (1 to 0). A key not counted
  // stays so (false).
  bool remove(std::uint64_t key) {
    if (slots_.empty()) return false;
    Slot& slot = slots_[find(key)];
    if (!slot.used || slot.count == 0) return false;  // not counted: nothing to remove
    if (--slot.count == 0) --counted_;
    return slot.count == 0;
  }
  std::uint32_t count(std::uint64_t key) const {
    if (slots_.empty()) return 0;
    const Slot& slot = slots_[find(key)];
    return slot.used ? slot.count : 0;
  }
  std::size_t size() const { return counted_; }  // keys counted (a count above zero)
  std::size_t memoryBytes() const { return slots_.capacity() * sizeof(Slot); }

 private:
  struct Slot {
    std::uint64_t key = 0;
    std::uint32_t count = 0;
    bool used = false;
  };
  std::size_t find(std::uint64_t key) const {
    std::uint64_t z = key + 0x9e3779b97f4a7c15ull;  // SplitMix64's finalizer
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = std::size_t(z ^ (z >> 31)) & mask;; i = (i + 1) & mask)
      if (!slots_[i].used || slots_[i].key == key) return i;
  }
  // Keeps the keys counted (drops those at zero), in a table twice as large as they need.
  void rehash() {
    std::vector<Slot> old = std::move(slots_);
    std::size_t capacity = 16;
    while (capacity < 4 * (counted_ + 1)) capacity *= 2;
    slots_.assign(capacity, Slot{});
    used_ = 0;
    for (const Slot& slot : old)
      if (slot.used && slot.count > 0) {
        slots_[find(slot.key)] = slot;
        ++used_;
      }
  }

  std::vector<Slot> slots_;
  std::size_t used_ = 0, counted_ = 0;
};

}  // namespace penumbra
