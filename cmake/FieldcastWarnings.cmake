# fieldcast::warnings — the warning set every Fieldcast target compiles with (PRIVATE link).
# fieldcast::arch — the instruction-set choice (generic x86-64 unless FIELDCAST_NATIVE is on) and
# floating-point contraction off.
add_library(fieldcast_warnings INTERFACE)
add_library(fieldcast::warnings ALIAS fieldcast_warnings)
target_compile_options(fieldcast_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
  -Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual -Wnull-dereference
  -Wimplicit-fallthrough -Wformat=2)
if(FIELDCAST_WERROR)
  target_compile_options(fieldcast_warnings INTERFACE -Werror)
endif()

add_library(fieldcast_arch INTERFACE)
add_library(fieldcast::arch ALIAS fieldcast_arch)
# No fused multiply-adds behind the code's back: with -march=native GCC and Clang would fuse some
# a·b + c and not others, so the caster's SIMD and scalar paths (tested to agree to the bit) and
# the golden images would differ between a native and a portable build.
target_compile_options(fieldcast_arch INTERFACE -ffp-contract=off)
if(FIELDCAST_NATIVE)
  # Highway 1.0.3 (Debian 12) leaves AVX3_DL out of its dynamic targets even when the baseline has
  # it (a Zen 4 or Ice Lake's -march=native) and stops with "best baseline should be included in
  # dynamic targets"; asking for AVX3_DL puts it back (on a CPU without it, a target compiled and
  # never run).
  target_compile_options(fieldcast_arch INTERFACE -march=native)
  target_compile_definitions(fieldcast_arch INTERFACE HWY_WANT_AVX3_DL)
endif()
