#pragma once
// The process's peak resident memory, for the `peak_memory_bytes` of the JSON reports.

#include <cstddef>

namespace penumbra::cli {

// VmHWM of /proc/self/status in bytes; 0 where /proc is unavailable.
std::size_t peakMemoryBytes();

}  // namespace penumbra::cli
