#pragma once
// The machine's own stalls while a test runs the service: the stall probe (tools/rig/StallProbe.h,
// a SCHED_FIFO thread pinned to each CPU, waking every millisecond) runs beside it. A virtual
// machine whose CPUs the hypervisor takes away for 100 ms stops the field thread whatever its
// priority; the fields due then are the machine's misses, not the service's. Where the probe
// cannot run pinned at real-time priority (an unprivileged runner) it explains nothing.

#include <MachineStalls.h>
#include <StallProbe.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace fieldcast::testing {

/// The field period of the tests' runs: 59.94 Hz, rounded to the nanosecond.
constexpr std::int64_t kNtscFieldPeriodNs = 16'683'333;

class MachineStallWatch {
 public:
  MachineStallWatch() : mThread([this] { mRun = tools::runStallProbe(tools::StallProbeOptions{}, mStop); }) {}
  ~MachineStallWatch() { stop(); }
  MachineStallWatch(const MachineStallWatch&) = delete;
  MachineStallWatch& operator=(const MachineStallWatch&) = delete;

  /// Stops the probe; the stalls it saw (none when it could not run pinned at real-time priority).
  const std::vector<tools::MachineStall>& stop() {
    if (mThread.joinable()) {
      mStop.store(true);
      mThread.join();
      const bool trusted = !mRun.cpus.empty() && std::all_of(mRun.cpus.begin(), mRun.cpus.end(),
                                                             [](const auto& cpu) { return cpu.realtime; });
      if (!trusted) mRun.stalls.clear();
    }
    return mRun.stalls;
  }

  /// The fields of `fieldPeriodNs` the machine's stalls may have cost (stops the probe).
  int fieldsDueInStalls(std::int64_t fieldPeriodNs = kNtscFieldPeriodNs) {
    return tools::fieldsDueInStalls(stop(), fieldPeriodNs);
  }
  /// Milliseconds of the time from `fromNs` to `toNs` (CLOCK_MONOTONIC) the machine stood still
  /// (stops the probe).
  double stalledMsBetween(std::int64_t fromNs, std::int64_t toNs) {
    return static_cast<double>(tools::stalledNsBetween(stop(), fromNs, toNs)) * 1e-6;
  }

 private:
  std::atomic<bool> mStop{false};
  tools::StallProbeRun mRun;
  std::thread mThread;
};

}  // namespace fieldcast::testing
