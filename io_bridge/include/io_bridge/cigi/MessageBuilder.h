#pragma once
// Builds one CIGI 3.3 message (one UDP datagram): the leading control packet, then any number
// of packets of the same direction, all in one byte order.
//
//   HostMessageBuilder host(swappedByteOrder());   // a host of the other byte order
//   host.start(IgControl{...});
//   host.add(EntityControl{...});
//   socket.send(host.bytes());
//
// IgMessageBuilder starts with Start of Frame and takes the IG's responses. Our own byte order
// is the default; the leading packet carries the byte-swap magic in the chosen order.

#include <io_bridge/cigi/ByteOrder.h>
#include <io_bridge/cigi/Codec.h>
#include <io_bridge/cigi/Packets.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>
#include <variant>
#include <vector>

namespace fieldcast::io::cigi {

/// The largest UDP payload over IPv4 (65535 − 8 − 20).
inline constexpr std::size_t kMaxDatagramBytes = 65507;

namespace detail {
template <class T, class Variant>
struct IsAlternative;
template <class T, class... Ts>
struct IsAlternative<T, std::variant<Ts...>> : std::bool_constant<(std::is_same_v<T, Ts> || ...)> {};
}  // namespace detail

/// One message of the direction whose packets are `Packet` and whose leading packet is `Lead`.
template <class Lead, class Packet>
class MessageBuilder {
 public:
  /// `maxBytes` bounds the message (a datagram's payload); add() refuses what would not fit.
  /// The buffer is allocated here once: start() and add() never allocate.
  explicit MessageBuilder(ByteOrder order = nativeByteOrder(), std::size_t maxBytes = kMaxDatagramBytes)
      : mOrder(order), mBuffer(maxBytes < Lead::kSize ? std::size_t{Lead::kSize} : maxBytes) {}

  /// Starts a new message with its leading packet (earlier content is dropped).
  void start(const Lead& lead) noexcept {
    mSize = 0;
    append(lead);
  }

  /// Appends a packet. Returns false (and leaves the message unchanged) when no message was
  /// started or the packet would not fit within maxBytes.
  template <class P>
  bool add(const P& packet) noexcept {
    static_assert(detail::IsAlternative<P, Packet>::value, "not a packet of this direction");
    static_assert(!std::is_same_v<P, Lead>, "the leading packet is given to start()");
    if (mSize == 0 || mSize + P::kSize > mBuffer.size()) return false;
    append(packet);
    return true;
  }

  /// The message so far.
  std::span<const std::uint8_t> bytes() const noexcept { return {mBuffer.data(), mSize}; }
  ByteOrder byteOrder() const noexcept { return mOrder; }

 private:
  template <class P>
  void append(const P& packet) noexcept {
    encode(packet, mOrder, std::span<std::uint8_t, P::kSize>(mBuffer.data() + mSize, P::kSize));
    mSize += P::kSize;
  }

  ByteOrder mOrder;
  std::vector<std::uint8_t> mBuffer;  // maxBytes long; the message is its first mSize bytes
  std::size_t mSize = 0;
};

/// Host → IG: IG Control, then control packets and requests.
using HostMessageBuilder = MessageBuilder<IgControl, HostPacket>;
/// IG → host: Start of Frame, then responses.
using IgMessageBuilder = MessageBuilder<StartOfFrame, IgPacket>;

}  // namespace fieldcast::io::cigi
