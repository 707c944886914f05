#pragma once
// A frame of uniform random bytes: the worst case for interpolation error, and every byte value
// a kernel may meet.

#include <fieldcast/Image.h>

#include <cstdint>
#include <random>

namespace fieldcast::warp::test {

inline Image noiseImage(int w, int h, PixelFormat format, unsigned seed) {
  Image img(w, h, format);
  std::mt19937 rng(seed);
  for (std::uint8_t& b : img.bytes()) b = static_cast<std::uint8_t>(rng() & 0xff);
  return img;
}

}  // namespace fieldcast::warp::test
