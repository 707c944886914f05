#pragma once
// Fixed-offset field access in one CIGI packet, in a chosen byte order. The packet's extent is
// a fixed-size span, so every offset is checked against it at compile time where the offset is
// a constant (all of Codec.cpp's are).

#include <io_bridge/cigi/ByteOrder.h>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

namespace fieldcast::io::cigi::detail {

template <class T>
constexpr T byteSwap(T v) noexcept {
  static_assert(sizeof(T) == 2 || sizeof(T) == 4 || sizeof(T) == 8);
  if constexpr (sizeof(T) == 2) return static_cast<T>(__builtin_bswap16(static_cast<std::uint16_t>(v)));
  if constexpr (sizeof(T) == 4) return static_cast<T>(__builtin_bswap32(static_cast<std::uint32_t>(v)));
  if constexpr (sizeof(T) == 8) return static_cast<T>(__builtin_bswap64(static_cast<std::uint64_t>(v)));
}

/// Writes fields into one packet's bytes.
template <std::size_t N>
class FieldWriter {
 public:
  FieldWriter(std::span<std::uint8_t, N> bytes, ByteOrder order) noexcept
      : mBytes(bytes), mSwap(order != nativeByteOrder()) {
    std::memset(mBytes.data(), 0, N);  // reserved bytes and bits are zero
  }
  template <std::size_t Offset>
  void u8(std::uint8_t v) noexcept {
    static_assert(Offset < N);
    mBytes[Offset] = v;
  }
  template <std::size_t Offset>
  void u16(std::uint16_t v) noexcept {
    put<Offset>(v);
  }
  template <std::size_t Offset>
  void u32(std::uint32_t v) noexcept {
    put<Offset>(v);
  }
  template <std::size_t Offset>
  void f32(float v) noexcept {
    put<Offset>(std::bit_cast<std::uint32_t>(v));
  }
  template <std::size_t Offset>
  void f64(double v) noexcept {
    put<Offset>(std::bit_cast<std::uint64_t>(v));
  }

 private:
  template <std::size_t Offset, class U>
  void put(U v) noexcept {
    static_assert(Offset + sizeof(U) <= N);
    if (mSwap) v = byteSwap(v);
    std::memcpy(mBytes.data() + Offset, &v, sizeof(U));
  }
  std::span<std::uint8_t, N> mBytes;
  bool mSwap;
};

/// Reads fields from one packet's bytes.
template <std::size_t N>
class FieldReader {
 public:
  FieldReader(std::span<const std::uint8_t, N> bytes, ByteOrder order) noexcept
      : mBytes(bytes), mSwap(order != nativeByteOrder()) {}
  template <std::size_t Offset>
  std::uint8_t u8() const noexcept {
    static_assert(Offset < N);
    return mBytes[Offset];
  }
  template <std::size_t Offset>
  std::uint16_t u16() const noexcept {
    return get<Offset, std::uint16_t>();
  }
  template <std::size_t Offset>
  std::uint32_t u32() const noexcept {
    return get<Offset, std::uint32_t>();
  }
  template <std::size_t Offset>
  float f32() const noexcept {
    return std::bit_cast<float>(get<Offset, std::uint32_t>());
  }
  template <std::size_t Offset>
  double f64() const noexcept {
    return std::bit_cast<double>(get<Offset, std::uint64_t>());
  }

 private:
  template <std::size_t Offset, class U>
  U get() const noexcept {
    static_assert(Offset + sizeof(U) <= N);
    U v;
    std::memcpy(&v, mBytes.data() + Offset, sizeof(U));
    return mSwap ? byteSwap(v) : v;
  }
  std::span<const std::uint8_t, N> mBytes;
  bool mSwap;
};

/// One bit of a flags byte.
constexpr std::uint8_t bit(bool on, unsigned shift) noexcept { return on ? static_cast<std::uint8_t>(1u << shift) : 0; }
/// A bit field of a flags byte: `value` masked to `width` bits, moved to `shift`.
constexpr std::uint8_t bits(unsigned value, unsigned shift, unsigned width) noexcept {
  return static_cast<std::uint8_t>((value & ((1u << width) - 1)) << shift);
}
/// Reads a bit field back.
constexpr unsigned field(std::uint8_t byte, unsigned shift, unsigned width) noexcept {
  return (byte >> shift) & ((1u << width) - 1);
}
constexpr bool flag(std::uint8_t byte, unsigned shift) noexcept { return ((byte >> shift) & 1u) != 0; }

}  // namespace fieldcast::io::cigi::detail
