// The process's and the machine's memory, for the run engine's memory budget
// (docs/architecture.md "Memory"): the peak resident set so far (getrusage ru_maxrss), the
// current resident set (/proc/self/statm) and the memory available to new allocations
// (/proc/meminfo MemAvailable).
#pragma once
#include <cstdint>

namespace fovsim {

// Peak resident set size of this process since it started, bytes (ru_maxrss is in KiB on
// Linux).
uint64_t peak_rss_bytes();
// Resident set size now, bytes; 0 when /proc/self/statm cannot be read.
uint64_t current_rss_bytes();
// MemAvailable of /proc/meminfo, bytes; 0 when it cannot be read.
uint64_t available_memory_bytes();

}  // namespace fovsim
