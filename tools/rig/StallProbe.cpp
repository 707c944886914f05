// One real-time thread per CPU, each waking at absolute times; late wake-ups are the stalls.
#include "StallProbe.h"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <exception>
#include <thread>

namespace fieldcast::tools {
namespace {

std::int64_t monotonicNs() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

void sleepUntil(std::int64_t ns) {
  const timespec t{static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, nullptr) == EINTR) {
  }
}

void probeOneCpu(int cpu, const StallProbeOptions& options, const std::atomic<bool>& stop,
                 StallProbeRun::PerCpu& result, std::vector<MachineStall>& stalls) {
  result.cpu = cpu;
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  const int pinError = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
  if (pinError != 0) result.problem = std::string("not pinned: ") + std::strerror(pinError);
  sched_param param{};
  param.sched_priority = options.fifoPriority;
  if (const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param); error != 0) {
    result.problem += (result.problem.empty() ? "" : "; ") + std::string("SCHED_FIFO refused: ") + std::strerror(error);
  } else {
    result.realtime = pinError == 0;
  }
  const std::int64_t periodNs = std::chrono::nanoseconds(options.period).count();
  const std::int64_t thresholdNs = std::chrono::nanoseconds(options.threshold).count();
  std::int64_t due = monotonicNs() + periodNs;
  std::int64_t latestNs = 0;
  while (!stop.load(std::memory_order_relaxed)) {
    sleepUntil(due);
    const std::int64_t woke = monotonicNs();
    ++result.wakeUps;
    latestNs = std::max(latestNs, woke - due);
    if (woke - due >= thresholdNs) stalls.push_back({cpu, due, woke});
    // After a stall, on from now: the wake-ups it cost are not owed
    due = std::max(due + periodNs, woke + periodNs / 2);
  }
  result.latestMs = static_cast<double>(latestNs) * 1e-6;
}

}  // namespace

StallProbeRun runStallProbe(const StallProbeOptions& options, const std::atomic<bool>& stop) {
  // The CPUs this process may run on (a container's or taskset's share, not all the machine's)
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  std::vector<int> cpus;
  if (sched_getaffinity(0, sizeof allowed, &allowed) == 0) {
    for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu)
      if (CPU_ISSET(cpu, &allowed)) cpus.push_back(cpu);
  }
  if (cpus.empty()) cpus.push_back(0);
  StallProbeRun run;
  run.cpus.resize(cpus.size());
  std::vector<std::vector<MachineStall>> stallsByCpu(cpus.size());
  for (auto& s : stallsByCpu) s.reserve(4096);  // a real-time thread should not allocate (unless there are more)
  std::vector<std::thread> threads(cpus.size());
  for (std::size_t i = 0; i < cpus.size(); ++i) {
    try {
      threads[i] = std::thread([&, i]() noexcept {
        try {
          probeOneCpu(cpus[i], options, stop, run.cpus[i], stallsByCpu[i]);
        } catch (const std::exception& e) {  // a stall record it could not store
          run.cpus[i].problem += std::string(run.cpus[i].problem.empty() ? "" : "; ") + e.what();
          run.cpus[i].realtime = false;
        }
      });
    } catch (const std::exception& e) {  // no thread for this CPU: it is not probed (no resources)
      run.cpus[i].cpu = cpus[i];
      run.cpus[i].problem = std::string("probe thread not started: ") + e.what();
    }
  }
  for (std::thread& t : threads)
    if (t.joinable()) t.join();
  for (const auto& s : stallsByCpu) run.stalls.insert(run.stalls.end(), s.begin(), s.end());
  std::sort(run.stalls.begin(), run.stalls.end(),
            [](const MachineStall& a, const MachineStall& b) { return a.dueNs < b.dueNs; });
  return run;
}

}  // namespace fieldcast::tools
