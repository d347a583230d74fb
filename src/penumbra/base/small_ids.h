#pragma once
// A short list of ids held in the object itself, on the heap only past kInline ids: for keys made
// by the hundred thousand every frame (the discontinuity mesh's EEE trace keys, each the polygons
// of two or three edges), where a vector's allocation per key cost more than the key's use.

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace penumbra {

class SmallIds {
 public:
  static constexpr std::size_t kInline = 12;

  void push_back(int id) {
    if (size_ < kInline) {
      inline_[size_] = id;
    } else {
      if (size_ == kInline) heap_.assign(inline_.begin(), inline_.end());
      heap_.push_back(id);
    }
    ++size_;
  }
  std::size_t size() const { return size_; }
  const int* begin() const { return size_ <= kInline ? inline_.data() : heap_.data(); }
  const int* end() const { return begin() + size_; }
  // Bytes held on the heap.
  std::size_t heapBytes() const { return heap_.capacity() * sizeof(int); }

  friend bool operator==(const SmallIds& a, const SmallIds& b) {
    return a.size_ == b.size_ && std::equal(a.begin(), a.end(), b.begin());
  }

 private:
  std::array<int, kInline> inline_{};
  std::size_t size_ = 0;
  std::vector<int> heap_;  // every id, once there are more than kInline
};

}  // namespace penumbra
