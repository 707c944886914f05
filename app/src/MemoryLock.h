#pragma once
// Keeping the field thread's memory resident (DESIGN.md §5): a page fault on the per-field path
// costs a deadline. The service locks its pages where the system allows it and the field thread
// touches its stack before its first field.

#include <cstddef>
#include <string>

namespace fieldcast::app {

/// What lockMemory() got.
struct MemoryLockResult {
  bool locked = false;
  std::string report;  ///< one line: granted, or why not
};

/// mlockall(MCL_CURRENT | MCL_FUTURE), tried only where it cannot make later allocations fail:
/// with an unlimited RLIMIT_MEMLOCK or as root (CAP_IPC_LOCK). Never throws; refusal is not an error.
MemoryLockResult lockMemory() noexcept;

/// Touches `bytes` of the calling thread's stack so that its pages are mapped before the
/// real-time loop needs them. RT-safe once done.
void prefaultStack(std::size_t bytes = 256 * 1024) noexcept;

}  // namespace fieldcast::app
