#pragma once
// A short list of ids held in the object itself, on the heap only past N ids: for lists made by
// the hundred thousand every frame (the discontinuity mesh's surfaces' hinge polygons, its EEE
// trace keys, each the polygons of two or three edges), where a vector's allocation per list
// cost more than the list's use.

#include <algorithm>
#include <array>
#include <cstddef>
#include <initializer_list>
#include <vector>

namespace penumbra {

template <std::size_t N>
class SmallIds {
 public:
  static constexpr std::size_t kInline = N;

  SmallIds() = default;
  SmallIds(std::initializer_list<int> ids) { append(ids.begin(), ids.end()); }

  void push_back(int id) {
    if (size_ < kInline) {
      inline_[size_] = id;
    } else {
      if (size_ == kInline) heap_.assign(inline_.begin(), inline_.end());
      heap_.push_back(id);
    }
    ++size_;
  }
  template <class Iterator>
  void append(Iterator first, Iterator last) {
    for (; first != last; ++first) push_back(*first);
  }
  template <class Iterator>
  void assign(Iterator first, Iterator last) {
    clear();
    append(first, last);
  }
  void clear() {
    size_ = 0;
    heap_.clear();
  }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  int operator[](std::size_t i) const { return begin()[i]; }
  int front() const { return begin()[0]; }
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
