#include "MemoryLock.h"

#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <alloca.h>
#include <cerrno>
#include <cstring>

namespace fieldcast::app {

MemoryLockResult lockMemory() noexcept {
  try {
    rlimit limit{};
    const bool unlimited = getrlimit(RLIMIT_MEMLOCK, &limit) == 0 && limit.rlim_cur == RLIM_INFINITY;
    if (!unlimited && geteuid() != 0) {
      // With a finite limit, MCL_FUTURE would turn every allocation past it into a failure.
      return {false, "memory not locked: RLIMIT_MEMLOCK is " + std::to_string(limit.rlim_cur / 1024) +
                         " KiB (LimitMEMLOCK=infinity in the unit, or memlock unlimited, allows it)"};
    }
    if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
      return {false, std::string("memory not locked: mlockall refused: ") + std::strerror(errno)};
    }
    return {true, "memory locked (mlockall MCL_CURRENT | MCL_FUTURE)"};
  } catch (...) {
    return {false, "memory not locked (out of memory)"};
  }
}

void prefaultStack(std::size_t bytes) noexcept {
  auto* stack = static_cast<volatile unsigned char*>(alloca(bytes));
  const long page = sysconf(_SC_PAGESIZE);
  for (std::size_t at = 0; at < bytes; at += static_cast<std::size_t>(page > 0 ? page : 4096)) stack[at] = 0;
}

}  // namespace fieldcast::app
