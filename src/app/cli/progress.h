#pragma once
// Progress on stderr for long runs, only when stderr is a terminal and --quiet was not given.

#include <atomic>
#include <chrono>
#include <string>

namespace penumbra::cli {

class Progress {
 public:
  Progress(std::string label, long long total, bool quiet);
  ~Progress();
  // Thread-safe; redraws at most a few times per second.
  void advance(long long amount = 1);

 private:
  void draw(bool final);

  std::string label_;
  long long total_;
  bool enabled_;
  std::atomic<long long> done_{0};
  std::atomic<long long> lastDrawMs_{0};
  std::chrono::steady_clock::time_point start_;
};

}  // namespace penumbra::cli
