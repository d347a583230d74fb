#pragma once
// A process-wide registry of named counters (pbrt's --stats): modules add to counters by name,
// the CLI prints or reports them. Thread-safe; cheap enough for per-query counting.

#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace penumbra {

class Stats {
 public:
  static Stats& global();

  void add(const std::string& name, std::int64_t amount = 1);
  std::map<std::string, std::int64_t> snapshot() const;
  void reset();

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::int64_t> counters_;
};

}  // namespace penumbra
