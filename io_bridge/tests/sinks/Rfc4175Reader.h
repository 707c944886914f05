#pragma once
// An independent RFC 4175 reader for tests: parses packets field by field and checks every rule
// the sender must keep. Written from the RFC, not from the packetizer.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fieldcast::io::testing {

struct ParsedPacket {
  bool marker = false;
  int payloadType = 0;
  std::uint32_t extendedSequence = 0;
  std::uint32_t timestamp = 0;
  std::uint32_t ssrc = 0;
  struct Segment {
    int length = 0, line = 0, offsetPx = 0;
    bool field = false, continuation = false;
  };
  std::vector<Segment> segments;
};

inline std::uint32_t be16(const std::uint8_t* p) { return (std::uint32_t{p[0]} << 8) | p[1]; }
inline std::uint32_t be32(const std::uint8_t* p) { return (be16(p) << 16) | be16(p + 2); }

/// Parses one packet and copies its segments into `image` (rows of `lineBytes`). Returns an
/// error message, or empty when the packet is well formed.
inline std::string parsePacket(const std::uint8_t* p, std::size_t size, std::size_t lineBytes, int rows,
                               std::vector<std::uint8_t>& image, ParsedPacket& out) {
  if (size < 14 + 6) return "short packet";
  if ((p[0] >> 6) != 2) return "RTP version is not 2";
  if (p[0] & 0x3f) return "padding/extension/CSRC set";
  out.marker = (p[1] & 0x80) != 0;
  out.payloadType = p[1] & 0x7f;
  out.extendedSequence = (be16(p + 12) << 16) | be16(p + 2);
  out.timestamp = be32(p + 4);
  out.ssrc = be32(p + 8);
  std::size_t h = 14;
  for (;;) {
    if (h + 6 > size) return "line headers run past the packet";
    ParsedPacket::Segment s;
    s.length = static_cast<int>(be16(p + h));
    s.field = (p[h + 2] & 0x80) != 0;
    s.line = static_cast<int>(be16(p + h + 2) & 0x7fff);
    s.continuation = (p[h + 4] & 0x80) != 0;
    s.offsetPx = static_cast<int>(be16(p + h + 4) & 0x7fff);
    out.segments.push_back(s);
    h += 6;
    if (!s.continuation) break;
  }
  std::size_t d = h;
  for (const auto& s : out.segments) {
    if (s.length % 4 != 0) return "segment length not a whole number of pixel groups";
    if (s.offsetPx % 2 != 0) return "offset not at a pixel-group boundary";
    if (d + static_cast<std::size_t>(s.length) > size) return "segment data runs past the packet";
    if (s.line >= rows) return "line number out of range";
    const std::size_t at = static_cast<std::size_t>(s.offsetPx) / 2 * 4;
    if (at + static_cast<std::size_t>(s.length) > lineBytes) return "segment runs past the end of its line";
    std::copy(p + d, p + d + s.length,
              image.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(s.line) * lineBytes + at));
    d += static_cast<std::size_t>(s.length);
  }
  if (d != size) return "bytes after the last segment";
  return {};
}

}  // namespace fieldcast::io::testing
