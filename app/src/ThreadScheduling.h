#pragma once
// Scheduling of the service's threads (DESIGN.md §5): the field thread asks for real-time
// priority and may be pinned; render workers run at a lower niceness so that, on a machine with
// fewer cores than threads, the field thread wins the CPU when a field is due.

#include <string>

namespace fieldcast::app {

/// What a thread asks of the scheduler.
struct ThreadScheduling {
  bool realtime = false;  ///< SCHED_FIFO at `fifoPriority`
  int fifoPriority = 50;  ///< 1..99
  int nice = 0;           ///< niceness for SCHED_OTHER threads (−20..19); ignored when realtime is granted
  int cpu = -1;           ///< pin to this CPU; −1: no pinning
};

/// Applies `wanted` to the calling thread and names it (`name`, ≤ 15 characters, shows in top).
/// Never throws: returns one line saying what was granted and what was refused and why
/// (for example "SCHED_FIFO refused: Operation not permitted (needs CAP_SYS_NICE or an rtprio limit)").
std::string applyScheduling(const char* name, const ThreadScheduling& wanted) noexcept;

}  // namespace fieldcast::app
