#pragma once
// Byte order on the CIGI wire. CIGI 3 has no network byte order: a sender writes every
// multi-byte field in its own order and puts the byte-swap magic number 0x8000 in its leading
// packet (IG Control or Start of Frame); a receiver that reads 0x0080 there swaps every
// multi-byte field of that datagram.

#include <bit>
#include <cstdint>

namespace fieldcast::io::cigi {

/// The byte order multi-byte fields are written in.
enum class ByteOrder : std::uint8_t { Big, Little };

/// This machine's byte order (what we send in unless told otherwise).
constexpr ByteOrder nativeByteOrder() noexcept {
  return std::endian::native == std::endian::big ? ByteOrder::Big : ByteOrder::Little;
}

/// The other order: what a byte-swapped peer sends.
constexpr ByteOrder swappedByteOrder() noexcept {
  return nativeByteOrder() == ByteOrder::Big ? ByteOrder::Little : ByteOrder::Big;
}

/// The byte-swap magic number, as the sender's leading packet holds it in the sender's order.
inline constexpr std::uint16_t kByteSwapMagic = 0x8000;

}  // namespace fieldcast::io::cigi
