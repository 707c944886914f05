// A kernel that only says which level it was compiled for, dispatched as the real kernels are:
// the check that forcing a level reaches the dispatch.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "DispatchedLevel.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <fieldcast/SimdLevel.h>

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace fieldcast::HWY_NAMESPACE {

const char* CompiledLevel() {
  switch (HWY_TARGET) {
    case HWY_AVX3:
    case HWY_AVX3_DL:                                      // only in a native build for a CPU that has it
      return simdVbmiEnabled() ? "avx512vbmi" : "avx512";  // VBMI: the kernels' own choice
    case HWY_AVX2: return "avx2";
    case HWY_SSE4: return "sse4";
    case HWY_SSSE3: return "ssse3";
    case HWY_SCALAR:
    case HWY_EMU128: return "scalar";
    default: return hwy::TargetName(HWY_TARGET);
  }
}

}  // namespace fieldcast::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fieldcast {

HWY_EXPORT(CompiledLevel);

std::string dispatchedSimdLevel() { return HWY_DYNAMIC_DISPATCH(CompiledLevel)(); }

}  // namespace fieldcast
#endif
