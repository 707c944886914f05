// Levels by name over Highway's target bits (a lower bit is a better target).
#include <fieldcast/SimdLevel.h>

#include <hwy/highway.h>
#include <hwy/targets.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>

namespace fieldcast {
namespace {

struct NamedLevel {
  const char* name;
  std::int64_t targets;  // Highway's targets of this level
};
// AVX-512: Highway's AVX3, or its AVX3_DL where that is the baseline (a -march=native build on a
// CPU that has it carries no other target). One lane is HWY_SCALAR with GCC before 12.3 (which
// cannot build EMU128), else HWY_EMU128.
constexpr std::int64_t kAvx512 = HWY_AVX3 | HWY_AVX3_DL;
constexpr NamedLevel kLevels[] = {
    {"avx512", kAvx512},
    {"avx2", HWY_AVX2},
    {"sse4", HWY_SSE4},
    {"ssse3", HWY_SSSE3},
    {"scalar", HWY_SCALAR | HWY_EMU128},
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

/// What the CPU and this build can run, forcing aside: found once, on the first call (made at
/// start-up, before any level is forced), so later queries do not undo a forced level.
std::int64_t availableTargets() {
  static const std::int64_t available = [] {
    disableTargets(0);
    return runnableTargets();
  }();
  return available;
}

std::int64_t lowestBit(std::int64_t bits) { return bits & -bits; }

// "avx512vbmi": Highway's AVX-512 target with the kernels' VBMI paths on. Highway 1.0 has no
// target of its own for it: its AVX3_DL asks for VNNI, VBMI2, VAES and more besides, and is
// compiled only into a native build for a CPU that has them.
constexpr const char* kVbmiLevel = "avx512vbmi";
std::atomic<bool> gVbmiAllowed{true};  // off while a level below avx512vbmi is forced

bool cpuHasVbmi() noexcept {
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512vbmi");
}

}  // namespace

bool simdVbmiEnabled() noexcept {
  static const bool cpu = cpuHasVbmi();
  return cpu && gVbmiAllowed.load(std::memory_order_relaxed);
}

std::string simdLevel() {
  const std::int64_t targets = runnableTargets();
  if ((lowestBit(targets) & kAvx512) && simdVbmiEnabled()) return kVbmiLevel;
  for (const NamedLevel& level : kLevels)
    if (lowestBit(targets) & level.targets) return level.name;
  return hwy::TargetName(lowestBit(targets));  // a target without a name here
}

std::vector<std::string> simdLevels() {
  const std::int64_t available = availableTargets();
  std::vector<std::string> names;
  if ((available & kAvx512) && cpuHasVbmi()) names.emplace_back(kVbmiLevel);
  for (const NamedLevel& level : kLevels)
    if (available & level.targets) names.emplace_back(level.name);
  return names;
}

void forceSimdLevel(std::string_view level) {
  const std::int64_t available = availableTargets();
  if (level == "auto") {
    disableTargets(0);
    gVbmiAllowed.store(true, std::memory_order_relaxed);
    return;
  }
  if (level == kVbmiLevel && (available & kAvx512) && cpuHasVbmi()) {
    disableTargets(lowestBit(available & kAvx512) - 1);
    gVbmiAllowed.store(true, std::memory_order_relaxed);
    return;
  }
  for (const NamedLevel& named : kLevels) {
    if (level != named.name) continue;
    if ((available & named.targets) == 0) break;
    disableTargets(lowestBit(available & named.targets) - 1);  // every better target (a lower bit) off
    gVbmiAllowed.store(false, std::memory_order_relaxed);
    return;
  }
  std::string have;
  for (const std::string& name : simdLevels()) have += (have.empty() ? "" : ", ") + name;
  throw std::invalid_argument("SIMD level \"" + std::string(level) +
                              "\" is not one this machine runs (it has: " + have + ", or auto)");
}

void applySimdLevelFromEnvironment() {
  if (const char* level = std::getenv("FIELDCAST_SIMD"); level != nullptr && *level != '\0') forceSimdLevel(level);
}

}  // namespace fieldcast
