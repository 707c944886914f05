// fieldcast-stall-probe — records the machine's own stalls while a rig runs (scripts/rig.sh):
// one SCHED_FIFO thread per CPU wakes every millisecond; each wake-up late by the threshold or
// more is written to --out as cpu,due_ns,woke_ns (CLOCK_MONOTONIC, the clock of the channels'
// field logs), for fieldcast-rig --stalls. Runs until SIGTERM or SIGINT, or for --duration.
// Exits 1 without writing the file when a CPU's thread was not both pinned and SCHED_FIFO.
//   fieldcast-stall-probe --out out/rig/stalls.csv
#include "StallProbe.h"

#include <tools/OptionChecks.h>

#include <CLI/CLI.hpp>

#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

int main(int argc, char** argv) {
  using namespace fieldcast;
  CLI::App app{"fieldcast-stall-probe: when the machine itself stalled (a real-time thread per CPU woke late)"};
  std::string outPath;
  double durationS = 0, thresholdMs = 5, periodMs = 1;
  int priority = 95;
  app.add_option("--out", outPath, "write the stalls here (CSV: cpu,due_ns,woke_ns)")->required();
  app.add_option("--duration", durationS, "seconds to run; 0: until SIGTERM or SIGINT")
      ->check(tools::finiteRange(0, 86400, "s"));
  app.add_option("--threshold-ms", thresholdMs, "record wake-ups at least this late")
      ->check(tools::finiteRange(0.1, 1000, "ms"));
  app.add_option("--period-ms", periodMs, "wake-up period")->check(tools::finiteRange(0.1, 100, "ms"));
  app.add_option("--priority", priority, "SCHED_FIFO priority of the probe's threads")
      ->check(tools::intRange(1, 99, ""));
  CLI11_PARSE(app, argc, argv);

  // The signals are waited for here, not delivered to the probe's threads (they inherit the mask)
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  // A page fault of the probe's own must not look like a stall. Locking future mappings too is
  // safe only without a limit (a thread's stack past the limit would fail to map).
  rlimit limit{};
  if (getrlimit(RLIMIT_MEMLOCK, &limit) == 0 && limit.rlim_cur == RLIM_INFINITY) {
    if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) std::perror("fieldcast-stall-probe: mlockall (going on unlocked)");
  } else if (mlockall(MCL_CURRENT) != 0) {
    std::perror("fieldcast-stall-probe: mlockall (going on unlocked)");
  }

  tools::StallProbeOptions options;
  options.period = std::chrono::microseconds(static_cast<std::int64_t>(periodMs * 1000));
  options.threshold = std::chrono::microseconds(static_cast<std::int64_t>(thresholdMs * 1000));
  options.fifoPriority = priority;
  std::atomic<bool> stop{false};
  tools::StallProbeRun run;
  std::string failure;
  std::thread probe([&]() noexcept {
    try {
      run = tools::runStallProbe(options, stop);
    } catch (const std::exception& e) {  // a thread it could not start
      failure = e.what();
    }
  });
  if (durationS > 0) {
    // Until the duration is over or a signal comes (a SIGSTOP/SIGCONT pair interrupts the wait)
    const auto end =
        std::chrono::steady_clock::now() + std::chrono::nanoseconds(static_cast<std::int64_t>(durationS * 1e9));
    for (auto left = end - std::chrono::steady_clock::now(); left.count() > 0;
         left = end - std::chrono::steady_clock::now()) {
      const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
      const timespec wait{static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
      if (sigtimedwait(&signals, nullptr, &wait) > 0) break;
    }
  } else {
    int signal = 0;
    sigwait(&signals, &signal);
  }
  stop.store(true);
  probe.join();

  for (const auto& cpu : run.cpus) {
    std::size_t stalls = 0;
    for (const auto& s : run.stalls) stalls += s.cpu == cpu.cpu ? 1 : 0;
    std::printf("cpu %d: %llu wake-ups, %zu at least %.1f ms late, the latest %.3f ms late%s%s\n", cpu.cpu,
                static_cast<unsigned long long>(cpu.wakeUps), stalls, thresholdMs, cpu.latestMs,
                cpu.problem.empty() ? "" : "; ", cpu.problem.c_str());
  }
  if (!failure.empty()) {
    std::fprintf(stderr, "fieldcast-stall-probe: %s: the machine's stalls were not measured\n", failure.c_str());
    return 1;
  }
  // Without a real-time thread pinned to every CPU a late wake-up proves nothing of the machine:
  // no file, so that nothing is excused by it
  const bool measured = std::all_of(run.cpus.begin(), run.cpus.end(), [](const auto& c) { return c.realtime; });
  if (!measured) {
    std::fprintf(stderr,
                 "fieldcast-stall-probe: not a real-time thread pinned to every CPU (run as root, or grant "
                 "CAP_SYS_NICE): the machine's stalls were not measured\n");
    return 1;
  }
  try {
    tools::writeMachineStalls(outPath, run.stalls);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fieldcast-stall-probe: %s\n", e.what());
    return 1;
  }
  return 0;
}
