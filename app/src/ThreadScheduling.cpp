#include "ThreadScheduling.h"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace fieldcast::app {

std::string applyScheduling(const char* name, const ThreadScheduling& wanted) noexcept {
  try {
    std::string report = std::string(name) + ":";
    pthread_setname_np(pthread_self(), name);
    bool realtime = false;
    if (wanted.realtime) {
      sched_param param{};
      param.sched_priority = wanted.fifoPriority;
      const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
      if (error == 0) {
        realtime = true;
        report += " SCHED_FIFO priority " + std::to_string(wanted.fifoPriority);
      } else {
        report += std::string(" SCHED_FIFO refused: ") + std::strerror(error) +
                  " (needs CAP_SYS_NICE or LimitRTPRIO in the unit); running as SCHED_OTHER";
      }
    }
    if (!realtime && wanted.nice != 0) {
      // Niceness is per thread on Linux: setpriority on the thread id.
      const auto tid = static_cast<id_t>(syscall(SYS_gettid));
      if (setpriority(PRIO_PROCESS, tid, wanted.nice) == 0) {
        report += " nice " + std::to_string(wanted.nice);
      } else {
        report += std::string(" nice ") + std::to_string(wanted.nice) + " refused: " + std::strerror(errno);
      }
    }
    if (wanted.cpu >= 0) {
      cpu_set_t set;
      CPU_ZERO(&set);
      CPU_SET(static_cast<unsigned>(wanted.cpu), &set);
      const int error = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
      report += error == 0 ? " pinned to CPU " + std::to_string(wanted.cpu)
                           : " pinning to CPU " + std::to_string(wanted.cpu) + " refused: " + std::strerror(error);
    }
    if (!wanted.realtime && wanted.nice == 0 && wanted.cpu < 0) report += " default scheduling";
    return report;
  } catch (...) {
    return std::string(name) + ": scheduling report unavailable (out of memory)";
  }
}

}  // namespace fieldcast::app
