#pragma once
// What the warp's AVX-512 VBMI kernels (SampleBlockVbmi.cpp, PixelConversionVbmi.cpp) share: the
// target their functions are compiled for (the rest of the build stays baseline x86-64; they are
// called only where fieldcast::simdVbmiEnabled()), and the byte mask of a permute that fills
// bytes 0 and 2 of each 32-bit lane and zeroes bytes 1 and 3: two 16-bit values for vpmaddwd.

#include <immintrin.h>

#define FIELDCAST_VBMI __attribute__((target("avx512f,avx512bw,avx512vbmi")))

// GCC 12's AVX-512 intrinsics start some results from an undefined register, and its flow
// analysis then warns that the (unread) value may be uninitialized, in every file using them
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace fieldcast::warp {

constexpr __mmask64 kBytes0And2 = 0x5555555555555555ULL;

}  // namespace fieldcast::warp
