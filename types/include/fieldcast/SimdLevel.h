#pragma once
// The instruction-set level the vector kernels run at. The binaries target baseline x86-64 and
// carry each kernel compiled for several levels (Google Highway's dynamic dispatch); at start-up
// the widest level the CPU has is chosen. A level can be forced (`FIELDCAST_SIMD`, `--simd`) so
// tests run every level the machine has and a regression can be traced to one of them.
//
// Levels, best first: "avx512vbmi" (the AVX-512 kernels with their AVX-512 VBMI paths: byte
// permutes across a whole register), "avx512" (AVX-512 F/VL/DQ/BW), "avx2", "sse4", "ssse3",
// "scalar" (the kernels' Highway code without SIMD instructions). A FIELDCAST_NATIVE build
// carries only the level its compiler targets and the better ones.
//
// Call these at start-up or in a test, not while kernels run: forcing changes a process-wide
// dispatch.

#include <string>
#include <string_view>
#include <vector>

/// In a kernel's Highway per-target code: compiled for AVX-512, where its avx512vbmi paths may run
/// (Highway's AVX3; or AVX3_DL, which only a FIELDCAST_NATIVE build for a CPU that has it carries).
#define FIELDCAST_HWY_TARGET_IS_AVX512 (HWY_TARGET == HWY_AVX3 || HWY_TARGET == HWY_AVX3_DL)

namespace fieldcast {

/// The level the kernels dispatch to now.
std::string simdLevel();

/// The level a kernel dispatched now runs at, as the kernel itself knows it: simdLevel(), unless
/// the dispatch went astray.
std::string dispatchedSimdLevel();

/// The levels this build carries and this CPU can run, best first.
std::vector<std::string> simdLevels();

/// Makes the kernels run at `level` (one of simdLevels()) or, for "auto", at the best one.
/// Throws std::invalid_argument naming the levels this machine has, the level unchanged.
void forceSimdLevel(std::string_view level);

/// Whether the AVX-512 kernels may take their VBMI paths: the CPU has AVX-512 VBMI and the level
/// is "avx512vbmi" (the best, unless a lower one is forced). Any thread, RT-safe.
bool simdVbmiEnabled() noexcept;

/// Applies FIELDCAST_SIMD if it is set (see forceSimdLevel; throws the same way).
void applySimdLevelFromEnvironment();

}  // namespace fieldcast
