#pragma once
// Runs body(i) for i in [0, count) on `threads` threads (0: hardware concurrency), dynamic
// scheduling in chunks. The first exception thrown by a body is rethrown after all threads stop.

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace penumbra {

template <typename Body>
void parallelFor(long long count, int threads, Body&& body) {
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  threads = int(std::min<long long>(threads, std::max<long long>(1, count)));
  std::atomic<long long> next{0};
  std::exception_ptr failure;
  std::mutex failureMutex;
  const auto worker = [&] {
    constexpr long long kChunk = 16;
    for (;;) {
      const long long begin = next.fetch_add(kChunk);
      if (begin >= count) return;
      try {
        for (long long i = begin; i < std::min(count, begin + kChunk); ++i) body(i);
      } catch (...) {
        std::lock_guard lock(failureMutex);
        if (!failure) failure = std::current_exception();
        next = count;
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace penumbra
