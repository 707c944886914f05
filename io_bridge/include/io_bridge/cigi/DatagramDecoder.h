#pragma once
// Decodes whole CIGI 3.3 datagrams (one UDP payload = one CIGI message). A datagram is checked
// completely before any packet is handed out: it is accepted as a whole or rejected as a whole,
// with one counted reason. Never reads outside the given bytes; never throws.
//
// Host→IG datagrams (HostDatagramDecoder, the IG's side) must start with IG Control,
// IG→host datagrams (IgDatagramDecoder, a host's side) with Start of Frame. The leading packet
// gives the sender's byte order (its byte-swap magic) and version; every other packet is walked
// by its size byte. Packets the decoder does not know (other CIGI packets, user-defined ones,
// the other direction's) are skipped by their size and counted per opcode.

#include <io_bridge/cigi/ByteOrder.h>
#include <io_bridge/cigi/Packets.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace fieldcast::io::cigi {

/// Why a datagram was rejected.
enum class RejectReason : std::uint8_t {
  TooShort,                 ///< fewer than 2 bytes: not even a packet header
  NoLeadingControl,         ///< first packet is not IG Control (host→IG) / Start of Frame (IG→host)
  WrongMajorVersion,        ///< the leading packet's major version is not 3
  UnsupportedMinorVersion,  ///< CIGI 3.0/3.1 (minor version below 2, or a 16-byte leading packet)
  BadByteSwapMagic,         ///< the magic number reads neither 0x8000 nor 0x0080
  ZeroPacketSize,           ///< a packet's size byte is 0 (the walk could not advance)
  PacketPastEnd,            ///< a packet (or its 2-byte header) runs past the datagram's end
  WrongPacketSize,          ///< a packet the decoder knows has a size other than its 3.3 size
};
inline constexpr std::size_t kRejectReasonCount = 8;

/// A short lower-case name of the reason (for logs and summaries).
std::string_view toString(RejectReason reason) noexcept;

/// What a decoder has seen since it was made. Plain counters, read by the thread that decodes.
struct DecodeCounters {
  std::uint64_t datagramsAccepted = 0;
  std::uint64_t datagramsByteSwapped = 0;  ///< accepted datagrams whose sender's byte order is not ours
  std::uint64_t packetsDecoded = 0;        ///< packets handed out (leading packet included)
  std::uint64_t packetsSkipped = 0;        ///< unknown packets skipped by their size
  std::array<std::uint64_t, 256> skippedByOpcode{};
  std::array<std::uint64_t, kRejectReasonCount> datagramsRejected{};

  std::uint64_t rejected(RejectReason reason) const noexcept {
    return datagramsRejected[static_cast<std::size_t>(reason)];
  }
  std::uint64_t rejectedTotal() const noexcept;
};

/// The outcome of one datagram.
struct DecodeResult {
  std::optional<RejectReason> rejected;  ///< empty when the datagram was accepted
  ByteOrder senderOrder = nativeByteOrder();
  std::uint8_t minorVersion = 0;  ///< of the leading packet (accepted datagrams)
  std::size_t skippedCount = 0;   ///< unknown packets skipped

  bool accepted() const noexcept { return !rejected.has_value(); }
  explicit operator bool() const noexcept { return accepted(); }
  bool byteSwapped() const noexcept { return senderOrder != nativeByteOrder(); }
};

/// Decodes datagrams of one direction. `Packet` is HostPacket (IG side) or IgPacket (host side).
template <class Packet>
class DatagramDecoder {
 public:
  /// Checks the datagram and, when it is accepted, replaces `packets` with its decoded packets
  /// in wire order (the leading control packet first). A rejected datagram leaves `packets`
  /// empty. `packets` keeps its capacity, so a reused vector stops allocating once it has
  /// held the longest message.
  DecodeResult decode(std::span<const std::uint8_t> datagram, std::vector<Packet>& packets);

  const DecodeCounters& counters() const noexcept { return mCounters; }

 private:
  DecodeCounters mCounters;
};

/// The IG's decoder of host→IG datagrams (leading IG Control).
using HostDatagramDecoder = DatagramDecoder<HostPacket>;
/// A host's decoder of IG→host datagrams (leading Start of Frame).
using IgDatagramDecoder = DatagramDecoder<IgPacket>;

extern template class DatagramDecoder<HostPacket>;
extern template class DatagramDecoder<IgPacket>;

}  // namespace fieldcast::io::cigi
