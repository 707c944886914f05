// Datagram walk and validation of CIGI 3 messages (SISO-STD-013 §4: a message is one leading
// control packet followed by packets walked by their size byte; byte order from the leading
// packet's byte-swap magic).
#include <io_bridge/cigi/DatagramDecoder.h>

#include <io_bridge/cigi/Codec.h>

#include <numeric>
#include <type_traits>
#include <utility>

namespace fieldcast::io::cigi {

namespace {

/// What differs between the two directions: the leading packet and where its minor version is.
template <class Packet>
struct Direction;
template <>
struct Direction<HostPacket> {
  using Lead = IgControl;
  static constexpr std::size_t kMinorVersionByte = 4;
};
template <>
struct Direction<IgPacket> {
  using Lead = StartOfFrame;
  static constexpr std::size_t kMinorVersionByte = 5;
};

/// The CIGI 3.0/3.1 size of IG Control and Start of Frame (3.2 grew both to 24 bytes).
constexpr std::uint8_t kVersion30LeadSize = 16;
/// Minor versions whose layouts of our packets are 3.3's (3.2 lacks only Entity Control's
/// extrapolation bit, which a 3.2 host leaves zero).
constexpr std::uint8_t kLowestMinorVersion = 2;

/// Size of each opcode the direction decodes; 0 for the rest.
template <class Packet, std::size_t... I>
constexpr std::array<std::uint8_t, 256> makeSizeTable(std::index_sequence<I...>) {
  std::array<std::uint8_t, 256> table{};
  ((table[std::variant_alternative_t<I, Packet>::kOpcode] = std::variant_alternative_t<I, Packet>::kSize), ...);
  return table;
}
template <class Packet>
constexpr std::array<std::uint8_t, 256> kSizeByOpcode =
    makeSizeTable<Packet>(std::make_index_sequence<std::variant_size_v<Packet>>{});

/// Decodes the packet at `bytes` (already checked: known opcode, its size, inside the datagram)
/// and appends it.
template <class Packet, std::size_t... I>
void appendDecoded(std::uint8_t opcode, const std::uint8_t* bytes, ByteOrder order, std::vector<Packet>& packets,
                   std::index_sequence<I...>) {
  const auto tryOne = [&]<class P>(std::type_identity<P>) {
    if (opcode != P::kOpcode) return false;
    P& out = std::get<P>(packets.emplace_back(std::in_place_type<P>));
    decode(std::span<const std::uint8_t, P::kSize>(bytes, P::kSize), order, out);
    return true;
  };
  (tryOne(std::type_identity<std::variant_alternative_t<I, Packet>>{}) || ...);
}

}  // namespace

std::string_view toString(RejectReason reason) noexcept {
  switch (reason) {
    case RejectReason::TooShort: return "too short";
    case RejectReason::NoLeadingControl: return "no leading control packet";
    case RejectReason::WrongMajorVersion: return "wrong major version";
    case RejectReason::UnsupportedMinorVersion: return "unsupported minor version";
    case RejectReason::BadByteSwapMagic: return "bad byte-swap magic";
    case RejectReason::ZeroPacketSize: return "zero packet size";
    case RejectReason::PacketPastEnd: return "packet past end";
    case RejectReason::WrongPacketSize: return "wrong packet size";
  }
  return "unknown reason";
}

std::uint64_t DecodeCounters::rejectedTotal() const noexcept {
  return std::accumulate(datagramsRejected.begin(), datagramsRejected.end(), std::uint64_t{0});
}

template <class Packet>
DecodeResult DatagramDecoder<Packet>::decode(std::span<const std::uint8_t> datagram, std::vector<Packet>& packets) {
  using Lead = typename Direction<Packet>::Lead;
  constexpr const std::array<std::uint8_t, 256>& sizeByOpcode = kSizeByOpcode<Packet>;
  packets.clear();
  DecodeResult result;
  const auto reject = [&](RejectReason reason) {
    ++mCounters.datagramsRejected[static_cast<std::size_t>(reason)];
    result.rejected = reason;
    return result;
  };
  const std::size_t size = datagram.size();
  const std::uint8_t* d = datagram.data();

  // The leading packet: id, size, version, magic.
  if (size < 2) return reject(RejectReason::TooShort);
  if (d[0] != Lead::kOpcode) return reject(RejectReason::NoLeadingControl);
  const std::uint8_t leadSize = d[1];
  if (leadSize == 0) return reject(RejectReason::ZeroPacketSize);
  if (leadSize > size) return reject(RejectReason::PacketPastEnd);
  if (leadSize >= 3 && d[2] != kMajorVersion) return reject(RejectReason::WrongMajorVersion);
  if (leadSize != Lead::kSize) {
    return reject(leadSize == kVersion30LeadSize ? RejectReason::UnsupportedMinorVersion
                                                 : RejectReason::WrongPacketSize);
  }
  // The magic read big-endian: 0x8000 from a big-endian sender, 0x0080 from a little-endian one.
  const unsigned magic = (unsigned{d[6]} << 8) | d[7];
  if (magic == kByteSwapMagic) {
    result.senderOrder = ByteOrder::Big;
  } else if (magic == 0x0080u) {
    result.senderOrder = ByteOrder::Little;
  } else {
    return reject(RejectReason::BadByteSwapMagic);
  }
  result.minorVersion = static_cast<std::uint8_t>(d[Direction<Packet>::kMinorVersionByte] >> 4);
  if (result.minorVersion < kLowestMinorVersion) return reject(RejectReason::UnsupportedMinorVersion);

  // Walk the rest by size bytes; nothing is handed out unless the whole walk succeeds.
  std::size_t known = 1;
  for (std::size_t offset = leadSize; offset < size;) {
    if (size - offset < 2) return reject(RejectReason::PacketPastEnd);
    const std::uint8_t packetSize = d[offset + 1];
    if (packetSize == 0) return reject(RejectReason::ZeroPacketSize);
    if (packetSize > size - offset) return reject(RejectReason::PacketPastEnd);
    const std::uint8_t expected = sizeByOpcode[d[offset]];
    if (expected != 0 && packetSize != expected) return reject(RejectReason::WrongPacketSize);
    if (expected != 0) ++known;
    offset += packetSize;
  }

  // Accepted: decode the known packets, count the skipped ones.
  packets.reserve(known);
  for (std::size_t offset = 0; offset < size; offset += d[offset + 1]) {
    const std::uint8_t opcode = d[offset];
    if (sizeByOpcode[opcode] == 0) {
      ++result.skippedCount;
      ++mCounters.skippedByOpcode[opcode];
      continue;
    }
    appendDecoded(opcode, d + offset, result.senderOrder, packets,
                  std::make_index_sequence<std::variant_size_v<Packet>>{});
  }
  ++mCounters.datagramsAccepted;
  if (result.byteSwapped()) ++mCounters.datagramsByteSwapped;
  mCounters.packetsDecoded += packets.size();
  mCounters.packetsSkipped += result.skippedCount;
  return result;
}

template class DatagramDecoder<HostPacket>;
template class DatagramDecoder<IgPacket>;

}  // namespace fieldcast::io::cigi
