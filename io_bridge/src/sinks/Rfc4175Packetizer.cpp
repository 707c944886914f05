// RFC 4175 §4 (payload header) and §4.3 (payload data): segments of lines at pixel-group
// boundaries, several segments per packet, all line headers before all data.

#include <io_bridge/Rfc4175Packetizer.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace fieldcast::io {

namespace {

void put16(std::uint8_t* p, std::uint32_t v) noexcept {
  p[0] = static_cast<std::uint8_t>(v >> 8);
  p[1] = static_cast<std::uint8_t>(v);
}
void put32(std::uint8_t* p, std::uint32_t v) noexcept {
  put16(p, v >> 16);
  put16(p + 2, v & 0xffffu);
}

// Where the next packet starts: a line and a byte offset into it.
struct Cursor {
  int line = 0;
  std::size_t offsetBytes = 0;
};

// Visits the segments the packet starting at `at` holds and advances `at` past them. The packet
// takes whole lines while they fit and splits the first one that does not.
template <typename Visit>
void walkPacket(Cursor& at, int rows, std::size_t lineBytes, std::size_t payloadRoom, Visit&& visit) noexcept {
  std::size_t room = payloadRoom;
  while (at.line < rows && room >= kRfc4175LineHeaderBytes + kPgroupBytes) {
    const std::size_t fit = (room - kRfc4175LineHeaderBytes) / kPgroupBytes * kPgroupBytes;
    const std::size_t take = std::min(lineBytes - at.offsetBytes, fit);
    visit(at.line, at.offsetBytes, take);
    room -= kRfc4175LineHeaderBytes + take;
    at.offsetBytes += take;
    if (at.offsetBytes < lineBytes) break;  // the line continues in the next packet
    ++at.line;
    at.offsetBytes = 0;
  }
}

}  // namespace

void RtpPacketBatch::reserve(int maxPackets, int maxPacketBytes) {
  mStride = static_cast<std::size_t>(maxPacketBytes);
  mStorage.assign(static_cast<std::size_t>(maxPackets) * mStride, 0);
  mSizes.assign(static_cast<std::size_t>(maxPackets), 0);
  mCount = 0;
}

Rfc4175Packetizer::Rfc4175Packetizer(int widthPx, int mtuBytes, std::uint8_t payloadType, std::uint32_t ssrc,
                                     int ipUdpHeaderBytes)
    : mWidthPx(widthPx),
      mLineBytes(static_cast<std::size_t>((widthPx + kPgroupPixels - 1) / kPgroupPixels) * kPgroupBytes),
      mMaxPacketBytes(mtuBytes - ipUdpHeaderBytes),
      mPayloadType(static_cast<std::uint8_t>(payloadType & 0x7f)),
      mSsrc(ssrc) {
  if (widthPx < 1 || widthPx > 0x7fff) {
    throw std::invalid_argument("RFC 4175: width " + std::to_string(widthPx) + " outside 1..32767");
  }
  if (mMaxPacketBytes < kRfc4175FixedHeaderBytes + kRfc4175LineHeaderBytes + kPgroupBytes) {
    throw std::invalid_argument("RFC 4175: MTU " + std::to_string(mtuBytes) + " bytes cannot hold one pixel group");
  }
}

int Rfc4175Packetizer::packetsFor(int rows) const noexcept {
  const auto room = static_cast<std::size_t>(mMaxPacketBytes - kRfc4175FixedHeaderBytes);
  Cursor at;
  int packets = 0;
  while (at.line < rows) {
    walkPacket(at, rows, mLineBytes, room, [](int, std::size_t, std::size_t) {});
    ++packets;
  }
  return packets;
}

int Rfc4175Packetizer::packetize(const std::uint8_t* lines, std::size_t strideBytes, int rows, RtpField field,
                                 std::uint32_t rtpTimestamp, RtpPacketBatch& out) noexcept {
  const auto room = static_cast<std::size_t>(mMaxPacketBytes - kRfc4175FixedHeaderBytes);
  if (static_cast<std::size_t>(mMaxPacketBytes) > out.mStride) return 0;
  const std::uint32_t fBit = field == RtpField::Bottom ? 0x8000u : 0u;
  Cursor at;
  int n = 0;
  while (at.line < rows) {
    if (n >= out.capacity()) {
      out.mCount = 0;
      return 0;
    }
    std::uint8_t* packet = out.mStorage.data() + static_cast<std::size_t>(n) * out.mStride;
    // First pass: how many line headers, so the data can start right after them
    Cursor probe = at;
    int segments = 0;
    walkPacket(probe, rows, mLineBytes, room, [&](int, std::size_t, std::size_t) { ++segments; });
    const bool last = probe.line >= rows;

    packet[0] = 0x80;  // V=2, no padding, no extension, no CSRC
    packet[1] = static_cast<std::uint8_t>((last ? 0x80 : 0x00) | mPayloadType);
    put16(packet + 2, mSequence & 0xffffu);
    put32(packet + 4, rtpTimestamp);
    put32(packet + 8, mSsrc);
    put16(packet + 12, mSequence >> 16);

    // Second pass: line headers and data
    std::uint8_t* header = packet + kRfc4175FixedHeaderBytes;
    std::uint8_t* data = header + static_cast<std::size_t>(segments) * kRfc4175LineHeaderBytes;
    int index = 0;
    walkPacket(at, rows, mLineBytes, room, [&](int line, std::size_t offsetBytes, std::size_t length) {
      const auto offsetPx = static_cast<std::uint32_t>(offsetBytes / kPgroupBytes * kPgroupPixels);
      const std::uint32_t more = (++index < segments) ? 0x8000u : 0u;
      put16(header, static_cast<std::uint32_t>(length));
      put16(header + 2, fBit | (static_cast<std::uint32_t>(line) & 0x7fffu));
      put16(header + 4, more | (offsetPx & 0x7fffu));
      header += kRfc4175LineHeaderBytes;
      std::memcpy(data, lines + static_cast<std::size_t>(line) * strideBytes + offsetBytes, length);
      data += length;
    });
    out.mSizes[static_cast<std::size_t>(n)] = static_cast<std::size_t>(data - packet);
    ++mSequence;
    ++n;
  }
  out.mCount = n;
  return n;
}

}  // namespace fieldcast::io
