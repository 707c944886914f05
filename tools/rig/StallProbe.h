#pragma once
// A probe of the machine's own stalls (the idea of rt-tests' cyclictest, kept to what the rig
// needs: when, not only how long): one thread per CPU, pinned to it at a SCHED_FIFO priority
// above every thread of the IG's, waking every period at an absolute time. Any wake-up later
// than the threshold is recorded: for that long the CPU ran nothing of ours, whatever its
// priority — a virtual machine's CPU taken away by the hypervisor, or the kernel busy with
// interrupts off.

#include "MachineStalls.h"

#include <atomic>
#include <chrono>
#include <string>
#include <vector>

namespace fieldcast::tools {

struct StallProbeOptions {
  std::chrono::microseconds period{1000};
  std::chrono::microseconds threshold{5000};  ///< wake-ups at least this late are recorded
  int fifoPriority = 95;                      ///< the field thread runs at 50, the host link's at 45
};

struct StallProbeRun {
  std::vector<MachineStall> stalls;  ///< in the order of their due time
  struct PerCpu {
    int cpu = 0;
    std::uint64_t wakeUps = 0;
    double latestMs = 0;  ///< the latest wake-up, recorded or not
    /// Pinned and SCHED_FIFO: without both, a late wake-up may be the scheduler's choice (another
    /// thread had the CPU), not a stall of the machine
    bool realtime = false;
    std::string problem;  ///< why it is not pinned or not real-time, empty when it is both
  };
  std::vector<PerCpu> cpus;
};

/// Runs the probe on every CPU this process may run on until `stop` is set.
StallProbeRun runStallProbe(const StallProbeOptions& options, const std::atomic<bool>& stop);

}  // namespace fieldcast::tools
