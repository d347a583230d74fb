#include "penumbra/base/stats.h"

namespace penumbra {

Stats& Stats::global() {
  static Stats instance;
  return instance;
}

void Stats::add(const std::string& name, std::int64_t amount) {
  std::lock_guard lock(mutex_);
  counters_[name] += amount;
}

std::map<std::string, std::int64_t> Stats::snapshot() const {
  std::lock_guard lock(mutex_);
  return counters_;
}

void Stats::reset() {
  std::lock_guard lock(mutex_);
  counters_.clear();
}

}  // namespace penumbra
