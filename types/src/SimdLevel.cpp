// Levels by name over Highway's target bits (a lower bit is a better target).
#include <fieldcast/SimdLevel.h>

#include <hwy/highway.h>
#include <hwy/targets.h>

#include <cstdint>
#include <cstdlib>
#include <stdexcept>

namespace fieldcast {
namespace {

struct NamedLevel {
  const char* name;
  std::int64_t target;
};
constexpr NamedLevel kLevels[] = {
    {"avx512", HWY_AVX3}, {"avx2", HWY_AVX2}, {"sse4", HWY_SSE4}, {"ssse3", HWY_SSSE3}, {"scalar", HWY_SCALAR},
};

/// Highway's SupportedTargets, with the kernels' dispatch kept to it. In Highway 1.0 the call
/// itself points the dispatch at the best target the CPU has, disabled or not, and DisableTargets
/// only changes what it reports; so every call is followed by pointing the dispatch at what it
/// reported.
std::int64_t supportedTargets() {
  const std::int64_t targets = hwy::SupportedTargets();
  hwy::GetChosenTarget().Update(targets);
  return targets;
}

void disableTargets(std::int64_t disabled) {
  hwy::DisableTargets(disabled);
  supportedTargets();
}

/// The targets this build carries and the CPU runs, as Highway sees them now (forcing included).
std::int64_t runnableTargets() { return supportedTargets() & HWY_TARGETS; }

/// What forcing does not change: what the CPU could run, were nothing disabled.
std::int64_t availableTargets() {
  disableTargets(0);
  return runnableTargets();
}

}  // namespace

std::string simdLevel() {
  const std::int64_t targets = runnableTargets();
  for (const NamedLevel& level : kLevels)
    if (targets & level.target) return level.name;
  return hwy::TargetName(targets & -targets);  // a target without a name here (e.g. EMU128)
}

std::vector<std::string> simdLevels() {
  const std::int64_t current = runnableTargets();
  const std::int64_t available = availableTargets();
  std::vector<std::string> names;
  for (const NamedLevel& level : kLevels)
    if (available & level.target) names.emplace_back(level.name);
  // Put back what was forced: disabling every target better than the best current one
  const std::int64_t best = current & -current;
  disableTargets(best - 1);
  return names;
}

void forceSimdLevel(std::string_view level) {
  if (level == "auto") {
    disableTargets(0);
    return;
  }
  const std::int64_t available = availableTargets();
  for (const NamedLevel& named : kLevels) {
    if (level != named.name) continue;
    if ((available & named.target) == 0) break;
    disableTargets(named.target - 1);  // every better target (a lower bit) off
    return;
  }
  std::string have;
  for (const NamedLevel& named : kLevels)
    if (available & named.target) have += std::string(have.empty() ? "" : ", ") + named.name;
  throw std::invalid_argument("SIMD level \"" + std::string(level) +
                              "\" is not one this machine runs (it has: " + have + ", or auto)");
}

void applySimdLevelFromEnvironment() {
  if (const char* level = std::getenv("FIELDCAST_SIMD"); level != nullptr && *level != '\0') forceSimdLevel(level);
}

}  // namespace fieldcast
