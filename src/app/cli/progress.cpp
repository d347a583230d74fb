#include "progress.h"

#include <unistd.h>

#include <cstdio>

namespace penumbra::cli {

Progress::Progress(std::string label, long long total, bool quiet)
    : label_(std::move(label)),
      total_(total),
      enabled_(!quiet && isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() {
  if (enabled_) draw(true);
}

void Progress::advance(long long amount) {
  done_ += amount;
  if (!enabled_) return;
  const long long now = std::chrono::duration_cast<std::chrono::milliseconds>(
                            std::chrono::steady_clock::now() - start_)
                            .count();
  long long last = lastDrawMs_.load();
  if (now - last >= 200 && lastDrawMs_.compare_exchange_strong(last, now)) draw(false);
}

void Progress::draw(bool final) {
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const long long done = done_.load();
  std::fprintf(stderr, "\r%s: %lld/%lld (%.0f%%) %.1f s%s", label_.c_str(), done, total_,
               total_ > 0 ? 100.0 * done / total_ : 100.0, seconds, final ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace penumbra::cli
