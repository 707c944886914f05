#include <io_bridge/Rfc4175Packetizer.h>
#include <io_bridge/RtpVideoSink.h>

#include "Rfc4175Reader.h"

#include <gtest/gtest.h>

#include <numeric>

namespace fieldcast::io {
namespace {

using testing::ParsedPacket;
using testing::parsePacket;

struct Packed {
  std::vector<ParsedPacket> packets;
  std::vector<std::uint8_t> image;
};

// Packetises a field of `rows` lines with a byte pattern, parses it back and checks the rules
// that hold for every field: sizes within the MTU, one timestamp, consecutive sequence numbers,
// the marker on the last packet only, and every byte arriving exactly once where it belongs.
Packed roundTrip(int width, int rows, int mtu, RtpField field, std::uint32_t firstSequence = 1000) {
  Rfc4175Packetizer packer(width, mtu, 96, 0x12345678);
  packer.setSequence(firstSequence);
  const std::size_t lineBytes = packer.lineBytes();
  std::vector<std::uint8_t> source(lineBytes * static_cast<std::size_t>(rows));
  for (std::size_t i = 0; i < source.size(); ++i) source[i] = static_cast<std::uint8_t>((i * 7 + i / lineBytes) & 0xff);
  RtpPacketBatch batch;
  batch.reserve(packer.packetsFor(rows), packer.maxPacketBytes());
  const int n = packer.packetize(source.data(), lineBytes, rows, field, 4242, batch);
  EXPECT_EQ(n, packer.packetsFor(rows));
  Packed out;
  out.image.assign(source.size(), 0);
  std::vector<int> coverage(source.size(), 0);
  for (int i = 0; i < n; ++i) {
    EXPECT_LE(batch.size(i) + kIpUdpHeaderBytes, static_cast<std::size_t>(mtu)) << "packet " << i;
    ParsedPacket p;
    const std::string error = parsePacket(batch.data(i), batch.size(i), lineBytes, rows, out.image, p);
    EXPECT_EQ(error, "") << "packet " << i;
    EXPECT_EQ(p.marker, i == n - 1) << "packet " << i;
    EXPECT_EQ(p.timestamp, 4242u);
    EXPECT_EQ(p.ssrc, 0x12345678u);
    EXPECT_EQ(p.extendedSequence, firstSequence + static_cast<std::uint32_t>(i));
    for (const auto& s : p.segments) {
      EXPECT_EQ(s.field, field == RtpField::Bottom);
      const std::size_t at = static_cast<std::size_t>(s.line) * lineBytes + static_cast<std::size_t>(s.offsetPx) * 2;
      for (int b = 0; b < s.length; ++b) ++coverage[at + static_cast<std::size_t>(b)];
    }
    out.packets.push_back(p);
  }
  EXPECT_EQ(out.image, source);
  EXPECT_TRUE(std::all_of(coverage.begin(), coverage.end(), [](int c) { return c == 1; }));
  EXPECT_EQ(packer.sequence(), firstSequence + static_cast<std::uint32_t>(n));
  return out;
}

TEST(Rfc4175Packetizer, HdLinesSplitAcrossPackets) {
  // 1920 px = 3840 bytes per line; 1400-byte MTU leaves 1358 bytes of payload per packet.
  const Packed p = roundTrip(1920, 4, 1400, RtpField::TopOrProgressive);
  ASSERT_GE(p.packets.size(), 12u);
  // First packet: line 0 from pixel 0, as much as fits: (1358 - 6) / 4 pixel groups
  ASSERT_EQ(p.packets[0].segments.size(), 1u);
  EXPECT_EQ(p.packets[0].segments[0].line, 0);
  EXPECT_EQ(p.packets[0].segments[0].offsetPx, 0);
  EXPECT_EQ(p.packets[0].segments[0].length, 1352);
  EXPECT_EQ(p.packets[1].segments[0].offsetPx, 676);
  // The third packet finishes line 0 and starts line 1 in the same packet, continuation bit set
  ASSERT_EQ(p.packets[2].segments.size(), 2u);
  EXPECT_TRUE(p.packets[2].segments[0].continuation);
  EXPECT_FALSE(p.packets[2].segments[1].continuation);
  EXPECT_EQ(p.packets[2].segments[0].line, 0);
  EXPECT_EQ(p.packets[2].segments[1].line, 1);
  EXPECT_EQ(p.packets[2].segments[1].offsetPx, 0);
}

TEST(Rfc4175Packetizer, ShortLinesShareAPacket) {
  const Packed p = roundTrip(64, 20, 1400, RtpField::TopOrProgressive);  // 128-byte lines
  ASSERT_EQ(p.packets.size(), 2u);
  // 10 × (6 + 128) = 1340 of 1358 bytes, and the 18 left take the first 12 bytes of line 10
  ASSERT_EQ(p.packets[0].segments.size(), 11u);
  EXPECT_EQ(p.packets[0].segments[10].length, 12);
  EXPECT_EQ(p.packets[1].segments[0].line, 10);
  EXPECT_EQ(p.packets[1].segments[0].offsetPx, 6);
  EXPECT_EQ(p.packets[1].segments.back().line, 19);
  EXPECT_TRUE(p.packets[1].marker);
}

TEST(Rfc4175Packetizer, LastPacketOfABottomFieldCarriesMarkerAndFieldBit) {
  const Packed p = roundTrip(720, 243, 1400, RtpField::Bottom);
  EXPECT_TRUE(p.packets.back().marker);
  EXPECT_EQ(p.packets.back().segments.back().line, 242);
  const auto& last = p.packets.back().segments.back();
  EXPECT_EQ(last.offsetPx * 2 + last.length, 1440);  // ends exactly at the end of the line
}

TEST(Rfc4175Packetizer, OddWidthsPadTheLastPixelGroup) {
  for (int width : {1, 3, 719, 721, 1023}) {
    SCOPED_TRACE(width);
    roundTrip(width, 7, 1400, RtpField::TopOrProgressive);
  }
  Rfc4175Packetizer p(721, 1400, 96, 1);
  EXPECT_EQ(p.lineBytes(), 1444u);  // 361 pixel groups
}

TEST(Rfc4175Packetizer, TinyAndJumboMtus) {
  roundTrip(720, 5, kIpUdpHeaderBytes + kRfc4175FixedHeaderBytes + kRfc4175LineHeaderBytes + kPgroupBytes,
            RtpField::TopOrProgressive);  // one pixel group per packet
  roundTrip(1920, 9, 9000, RtpField::Bottom);
  EXPECT_THROW(Rfc4175Packetizer(720, 40, 96, 1), std::invalid_argument);
}

// An IPv6 destination's headers take 48 bytes of the MTU, not IPv4's 28: every packet and its
// headers still fit the MTU, and each carries 20 bytes less than to an IPv4 address.
TEST(Rfc4175Packetizer, IpV6PacketsLeaveRoomForTheLongerHeader) {
  constexpr int kMtu = 1500, kWidth = 1920, kRows = 64;
  Rfc4175Packetizer v4(kWidth, kMtu, 96, 1);
  Rfc4175Packetizer v6(kWidth, kMtu, 96, 1, kIpv6UdpHeaderBytes);
  EXPECT_EQ(v4.maxPacketBytes(), kMtu - 28);
  EXPECT_EQ(v6.maxPacketBytes(), kMtu - 48);
  std::vector<std::uint8_t> lines(v6.lineBytes() * kRows, 0x80);
  RtpPacketBatch batch;
  batch.reserve(v6.packetsFor(kRows), v6.maxPacketBytes());
  const int n = v6.packetize(lines.data(), v6.lineBytes(), kRows, RtpField::TopOrProgressive, 0, batch);
  ASSERT_GT(n, 0);
  for (int i = 0; i < n; ++i) EXPECT_LE(batch.size(i) + kIpv6UdpHeaderBytes, static_cast<std::size_t>(kMtu)) << i;
  EXPECT_GT(v6.packetsFor(kRows), v4.packetsFor(kRows));
}

TEST(Rfc4175Packetizer, ExtendedSequenceNumberWraps) {
  const Packed p = roundTrip(720, 8, 1400, RtpField::TopOrProgressive, 0xfffffffdu);
  ASSERT_GE(p.packets.size(), 5u);
  EXPECT_EQ(p.packets[2].extendedSequence, 0xffffffffu);
  EXPECT_EQ(p.packets[3].extendedSequence, 0u);
  // Low 16 bits wrap into the extended high bits at 0x0000ffff → 0x00010000 too
  const Packed q = roundTrip(720, 8, 1400, RtpField::TopOrProgressive, 0x0000fffeu);
  EXPECT_EQ(q.packets[2].extendedSequence, 0x00010000u);
}

TEST(Rfc4175Packetizer, TooSmallBatchWritesNothing) {
  Rfc4175Packetizer packer(720, 1400, 96, 1);
  std::vector<std::uint8_t> lines(packer.lineBytes() * 10);
  RtpPacketBatch batch;
  batch.reserve(2, packer.maxPacketBytes());
  EXPECT_EQ(packer.packetize(lines.data(), packer.lineBytes(), 10, RtpField::TopOrProgressive, 0, batch), 0);
}

TEST(RtpVideoSink, TimestampsRunAt90kHz) {
  EXPECT_EQ(RtpVideoSink::rtpTimestamp(TimePoint{std::chrono::seconds(1)}, 0), 90000u);
  EXPECT_EQ(RtpVideoSink::rtpTimestamp(TimePoint{std::chrono::seconds(1)}, 10), 90010u);
  // One 59.94 Hz field is 1501.5 ticks
  const RationalRate rate{60000, 1001};
  const auto t = [&](std::int64_t k) { return RtpVideoSink::rtpTimestamp(TimePoint{rate.tickOffset(k)}, 0); };
  EXPECT_EQ(t(2) - t(0), 3003u);
  // and the 32-bit counter wraps cleanly after 2^32 / 90000 s ≈ 13.3 h
  const TimePoint late{std::chrono::seconds(47722)};
  EXPECT_EQ(RtpVideoSink::rtpTimestamp(late + std::chrono::seconds(1), 0) - RtpVideoSink::rtpTimestamp(late, 0),
            90000u);
}

}  // namespace
}  // namespace fieldcast::io
