#pragma once
// The structure-aware target's reader of the fuzzer's bytes: a stream of small decisions (a choice
// among a few, a fraction, a flag), read front to back. Past the end every read gives zero, so
// every input, however short, describes something, and a mutation of a byte changes only the
// decisions it feeds. (libFuzzer's FuzzedDataProvider does the same, but ships inside clang's
// resource directory, which the GCC builds that replay the corpus do not have.)

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <span>

namespace penumbra::fuzz {

class FuzzInput {
 public:
  FuzzInput(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  std::uint8_t byte() { return offset_ < size_ ? data_[offset_++] : 0; }
  bool flag() { return byte() & 1; }
  // An integer in [low, high] (high - low < 256).
  int integer(int low, int high) { return low + int(byte() % unsigned(high - low + 1)); }
  // A fraction in [0, 1] with 16 bits: fine enough for positions, coarse enough that the fuzzer
  // meets the same value twice (coincident features come from the choices below, not from luck).
  double fraction() {
    const unsigned high = byte(), low = byte();
    return double(high << 8 | low) / 65535.0;
  }
  // A value in [low, high].
  double between(double low, double high) { return low + (high - low) * fraction(); }
  // Any double, bit for bit (NaN, infinities, subnormals included).
  double anyDouble() {
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i) bits = bits << 8 | byte();
    double value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
  }
  // One of `values`.
  template <typename T>
  T pick(std::initializer_list<T> values) {
    return std::data(values)[byte() % values.size()];
  }
  bool exhausted() const { return offset_ >= size_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
};

}  // namespace penumbra::fuzz
