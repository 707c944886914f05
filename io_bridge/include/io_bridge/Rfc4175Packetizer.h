#pragma once
// RTP payload format for uncompressed video, RFC 4175, for 8-bit YCbCr 4:2:2 (a pixel group of
// 4 bytes, Cb Y0 Cr Y1, covers 2 pixels: exactly a UYVY pair). Each packet:
//
//   RTP header (12 bytes, RFC 3550)  V=2, M = last packet of the field/frame, PT, sequence (low
//                                    16 bits of the extended sequence number), 90 kHz timestamp,
//                                    SSRC
//   extended sequence number (2)     high 16 bits
//   line headers (6 bytes each)      length in bytes (16) | F (1) line number (15) |
//                                    C (1) offset in pixels (15); C = another header follows
//   line data                        the segments, in header order
//
// A packet may carry the end of one line and the start of the next; a line longer than a packet
// is split at pixel-group boundaries. Line numbers count the rows of the field (or frame) from 0;
// F is 1 for the bottom field, 0 for the top field and for progressive frames.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fieldcast::io {

/// Bytes of IPv4 + UDP headers the MTU must also hold.
inline constexpr int kIpUdpHeaderBytes = 28;
/// Bytes of IPv6 + UDP headers (40 + 8) the MTU must hold on an IPv6 destination.
inline constexpr int kIpv6UdpHeaderBytes = 48;
/// RTP fixed header + extended sequence number.
inline constexpr int kRfc4175FixedHeaderBytes = 14;
/// One line-segment header.
inline constexpr int kRfc4175LineHeaderBytes = 6;
/// A 4:2:2 8-bit pixel group: 4 bytes for 2 pixels.
inline constexpr int kPgroupBytes = 4;
inline constexpr int kPgroupPixels = 2;

/// Packets of one field, in preallocated storage: packet i is bytes [i·stride, i·stride + size(i)).
class RtpPacketBatch {
 public:
  /// Allocates room for `maxPackets` packets of up to `maxPacketBytes`. Not RT-safe.
  void reserve(int maxPackets, int maxPacketBytes);
  int count() const noexcept { return mCount; }
  int capacity() const noexcept { return static_cast<int>(mSizes.size()); }
  const std::uint8_t* data(int i) const noexcept { return mStorage.data() + static_cast<std::size_t>(i) * mStride; }
  std::size_t size(int i) const noexcept { return mSizes[static_cast<std::size_t>(i)]; }

 private:
  friend class Rfc4175Packetizer;
  std::vector<std::uint8_t> mStorage;
  std::vector<std::size_t> mSizes;
  std::size_t mStride = 0;
  int mCount = 0;
};

/// Which field a packet's lines belong to (the F bit).
enum class RtpField : std::uint8_t { TopOrProgressive = 0, Bottom = 1 };

/// Cuts fields into RFC 4175 packets. Allocation-free after construction; RT-safe.
class Rfc4175Packetizer {
 public:
  /// `widthPx` may be odd (the last pixel group then carries one padding pixel). `mtuBytes` is
  /// the largest IP packet, of which `ipUdpHeaderBytes` are the IP and UDP headers (IPv4's 28, or
  /// IPv6's 48); throws std::invalid_argument when it cannot hold a line header and a pixel group,
  /// or widthPx exceeds the 15-bit offset.
  Rfc4175Packetizer(int widthPx, int mtuBytes, std::uint8_t payloadType, std::uint32_t ssrc,
                    int ipUdpHeaderBytes = kIpUdpHeaderBytes);

  int widthPx() const noexcept { return mWidthPx; }
  /// Bytes of one line on the wire: whole pixel groups.
  std::size_t lineBytes() const noexcept { return mLineBytes; }
  /// Largest RTP packet (UDP payload) this packetizer writes.
  int maxPacketBytes() const noexcept { return mMaxPacketBytes; }
  /// Packets a field of `rows` lines takes (exact).
  int packetsFor(int rows) const noexcept;

  /// Sets the 32-bit extended sequence number of the next packet.
  void setSequence(std::uint32_t extendedSequence) noexcept { mSequence = extendedSequence; }
  std::uint32_t sequence() const noexcept { return mSequence; }

  /// Packetises `rows` lines of 4:2:2 data (`lineBytes()` each, `strideBytes` apart) into `out`,
  /// which must have room for packetsFor(rows) packets of maxPacketBytes(). The last packet
  /// carries the marker bit. Returns the packets written (0 if `out` is too small).
  int packetize(const std::uint8_t* lines, std::size_t strideBytes, int rows, RtpField field,
                std::uint32_t rtpTimestamp, RtpPacketBatch& out) noexcept;

 private:
  int mWidthPx;
  std::size_t mLineBytes;
  int mMaxPacketBytes;
  std::uint8_t mPayloadType;
  std::uint32_t mSsrc;
  std::uint32_t mSequence = 0;
};

}  // namespace fieldcast::io
