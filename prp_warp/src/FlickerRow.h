#pragma once
// One row of the interlace flicker filter, [1 2 1]/4 across three frame rows, byte by byte: the
// scalar reference of the vector kernel (FlickerRowLanes.cpp), which must produce the same bytes.

#include <cstdint>

namespace fieldcast::warp::flicker {

inline void filterRowScalar(const std::uint8_t* above, const std::uint8_t* here, const std::uint8_t* below, int n,
                            std::uint8_t* out) noexcept {
  for (int i = 0; i < n; ++i) out[i] = static_cast<std::uint8_t>((above[i] + 2 * here[i] + below[i] + 2) >> 2);
}

/// filterRowScalar in SIMD lanes at the dispatched level.
void filterRowLanes(const std::uint8_t* above, const std::uint8_t* here, const std::uint8_t* below, int n,
                    std::uint8_t* out) noexcept;

}  // namespace fieldcast::warp::flicker
