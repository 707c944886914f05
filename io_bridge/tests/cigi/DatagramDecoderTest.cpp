// Whole-datagram decoding: both byte orders detected from the magic number, unknown packets
// skipped by size and counted, every rejection reason counted, truncation at every length.
#include <io_bridge/cigi/DatagramDecoder.h>
#include <io_bridge/cigi/MessageBuilder.h>

#include "SamplePackets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace {

using namespace fieldcast::io::cigi;
namespace td = fieldcast::io::cigi::testdata;

std::vector<HostPacket> allHostPackets() {
  return {td::sampleIgControl(),         td::sampleEntityControl(),
          td::sampleRateControl(),       td::sampleCelestialSphereControl(),
          td::sampleAtmosphereControl(), td::sampleViewControl(),
          td::sampleViewDefinition(),    td::sampleHatHotRequest(),
          td::sampleLosSegmentRequest(), td::sampleLosVectorRequest()};
}

std::vector<IgPacket> allIgPackets() {
  return {td::sampleStartOfFrame(), td::sampleHatHotResponse(), td::sampleHatHotExtendedResponse(),
          td::sampleLosResponse(), td::sampleLosExtendedResponse()};
}

/// A host message of every host packet, in `order`.
std::vector<std::uint8_t> hostMessage(ByteOrder order) {
  HostMessageBuilder builder(order);
  builder.start(td::sampleIgControl());
  EXPECT_TRUE(builder.add(td::sampleEntityControl()));
  EXPECT_TRUE(builder.add(td::sampleRateControl()));
  EXPECT_TRUE(builder.add(td::sampleCelestialSphereControl()));
  EXPECT_TRUE(builder.add(td::sampleAtmosphereControl()));
  EXPECT_TRUE(builder.add(td::sampleViewControl()));
  EXPECT_TRUE(builder.add(td::sampleViewDefinition()));
  EXPECT_TRUE(builder.add(td::sampleHatHotRequest()));
  EXPECT_TRUE(builder.add(td::sampleLosSegmentRequest()));
  EXPECT_TRUE(builder.add(td::sampleLosVectorRequest()));
  return {builder.bytes().begin(), builder.bytes().end()};
}

std::vector<std::uint8_t> igMessage(ByteOrder order) {
  IgMessageBuilder builder(order);
  builder.start(td::sampleStartOfFrame());
  EXPECT_TRUE(builder.add(td::sampleHatHotResponse()));
  EXPECT_TRUE(builder.add(td::sampleHatHotExtendedResponse()));
  EXPECT_TRUE(builder.add(td::sampleLosResponse()));
  EXPECT_TRUE(builder.add(td::sampleLosExtendedResponse()));
  return {builder.bytes().begin(), builder.bytes().end()};
}

/// The offsets at which packets start in `bytes` (walked by size; bytes assumed well formed).
std::vector<std::size_t> packetStarts(const std::vector<std::uint8_t>& bytes) {
  std::vector<std::size_t> starts;
  for (std::size_t at = 0; at < bytes.size(); at += bytes[at + 1]) starts.push_back(at);
  return starts;
}

TEST(CigiDatagramDecoder, DecodesAHostMessageFromEitherByteOrder) {
  for (const ByteOrder order : {ByteOrder::Big, ByteOrder::Little}) {
    HostDatagramDecoder decoder;
    std::vector<HostPacket> packets;
    const DecodeResult r = decoder.decode(hostMessage(order), packets);
    ASSERT_TRUE(r.accepted()) << toString(*r.rejected);
    EXPECT_EQ(r.senderOrder, order);
    EXPECT_EQ(r.byteSwapped(), order != nativeByteOrder());
    EXPECT_EQ(r.minorVersion, 3);
    EXPECT_EQ(r.skippedCount, 0u);
    EXPECT_EQ(packets, allHostPackets());
    EXPECT_EQ(decoder.counters().datagramsAccepted, 1u);
    EXPECT_EQ(decoder.counters().datagramsByteSwapped, order != nativeByteOrder() ? 1u : 0u);
    EXPECT_EQ(decoder.counters().packetsDecoded, 10u);
  }
}

TEST(CigiDatagramDecoder, DecodesAnIgMessageFromEitherByteOrder) {
  for (const ByteOrder order : {ByteOrder::Big, ByteOrder::Little}) {
    IgDatagramDecoder decoder;
    std::vector<IgPacket> packets;
    const DecodeResult r = decoder.decode(igMessage(order), packets);
    ASSERT_TRUE(r.accepted()) << toString(*r.rejected);
    EXPECT_EQ(r.senderOrder, order);
    EXPECT_EQ(packets, allIgPackets());
  }
}

TEST(CigiDatagramDecoder, SkipsUnknownPacketsBySizeAndCountsThem) {
  std::vector<std::uint8_t> bytes = hostMessage(ByteOrder::Big);
  // A user-defined packet (opcode 201, 12 bytes) after IG Control, and a Start of Frame (an
  // IG→host packet, unknown to the IG's decoder) at the end.
  const std::vector<std::uint8_t> userDefined = {201, 12, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};
  bytes.insert(bytes.begin() + IgControl::kSize, userDefined.begin(), userDefined.end());
  const std::vector<std::uint8_t> sof = igMessage(ByteOrder::Big);
  bytes.insert(bytes.end(), sof.begin(), sof.begin() + StartOfFrame::kSize);

  HostDatagramDecoder decoder;
  std::vector<HostPacket> packets;
  const DecodeResult r = decoder.decode(bytes, packets);
  ASSERT_TRUE(r.accepted()) << toString(*r.rejected);
  EXPECT_EQ(r.skippedCount, 2u);
  EXPECT_EQ(packets, allHostPackets());  // the walk resumed after each skipped packet
  EXPECT_EQ(decoder.counters().packetsSkipped, 2u);
  EXPECT_EQ(decoder.counters().skippedByOpcode[201], 1u);
  EXPECT_EQ(decoder.counters().skippedByOpcode[StartOfFrame::kOpcode], 1u);
}

/// Decodes `bytes` into a vector that held packets before; expects rejection for `reason`.
void expectRejected(const std::vector<std::uint8_t>& bytes, RejectReason reason) {
  HostDatagramDecoder decoder;
  std::vector<HostPacket> packets = allHostPackets();
  const DecodeResult r = decoder.decode(bytes, packets);
  ASSERT_FALSE(r.accepted());
  EXPECT_EQ(*r.rejected, reason) << "got " << toString(*r.rejected) << ", expected " << toString(reason);
  EXPECT_TRUE(packets.empty()) << "a rejected datagram hands out nothing";
  EXPECT_EQ(decoder.counters().rejected(reason), 1u);
  EXPECT_EQ(decoder.counters().rejectedTotal(), 1u);
  EXPECT_EQ(decoder.counters().datagramsAccepted, 0u);
  EXPECT_EQ(decoder.counters().packetsDecoded, 0u);
}

TEST(CigiDatagramDecoder, RejectsTooShort) {
  expectRejected({}, RejectReason::TooShort);
  expectRejected({IgControl::kOpcode}, RejectReason::TooShort);
}

TEST(CigiDatagramDecoder, RejectsAMessageWithoutLeadingIgControl) {
  std::vector<std::uint8_t> bytes = hostMessage(ByteOrder::Big);
  bytes.erase(bytes.begin(), bytes.begin() + IgControl::kSize);  // starts with Entity Control
  expectRejected(bytes, RejectReason::NoLeadingControl);
  expectRejected(igMessage(ByteOrder::Big), RejectReason::NoLeadingControl);  // Start of Frame first
}

TEST(CigiDatagramDecoder, RejectsAWrongMajorVersion) {
  std::vector<std::uint8_t> bytes = hostMessage(ByteOrder::Little);
  bytes[2] = 2;
  expectRejected(bytes, RejectReason::WrongMajorVersion);
  bytes[2] = 4;
  expectRejected(bytes, RejectReason::WrongMajorVersion);
}

TEST(CigiDatagramDecoder, RejectsCigi30And31) {
  std::vector<std::uint8_t> bytes = hostMessage(ByteOrder::Big);
  bytes[4] = static_cast<std::uint8_t>((bytes[4] & 0x0F) | 0x10);  // minor version 1
  expectRejected(bytes, RejectReason::UnsupportedMinorVersion);
  // A CIGI 3.0 IG Control is 16 bytes.
  std::vector<std::uint8_t> v30(bytes.begin(), bytes.begin() + 16);
  v30[1] = 16;
  expectRejected(v30, RejectReason::UnsupportedMinorVersion);
}

TEST(CigiDatagramDecoder, AcceptsCigi32) {
  std::vector<std::uint8_t> bytes = hostMessage(ByteOrder::Big);
  bytes[4] = static_cast<std::uint8_t>((bytes[4] & 0x0F) | 0x20);
  HostDatagramDecoder decoder;
  std::vector<HostPacket> packets;
  const DecodeResult r = decoder.decode(bytes, packets);
  ASSERT_TRUE(r.accepted());
  EXPECT_EQ(r.minorVersion, 2);
}

TEST(CigiDatagramDecoder, RejectsABadByteSwapMagic) {
  std::vector<std::uint8_t> bytes = hostMessage(ByteOrder::Big);
  bytes[6] = 0x12;
  bytes[7] = 0x34;
  expectRejected(bytes, RejectReason::BadByteSwapMagic);
  bytes[6] = 0x80;
  bytes[7] = 0x80;
  expectRejected(bytes, RejectReason::BadByteSwapMagic);
}

TEST(CigiDatagramDecoder, RejectsAZeroPacketSize) {
  std::vector<std::uint8_t> bytes = hostMessage(ByteOrder::Big);
  std::vector<std::uint8_t> leading = bytes;
  leading[1] = 0;
  expectRejected(leading, RejectReason::ZeroPacketSize);
  const std::vector<std::size_t> starts = packetStarts(bytes);
  bytes[starts[5] + 1] = 0;  // View Control's size
  expectRejected(bytes, RejectReason::ZeroPacketSize);
}

TEST(CigiDatagramDecoder, RejectsAPacketPastTheEnd) {
  std::vector<std::uint8_t> bytes = hostMessage(ByteOrder::Big);
  std::vector<std::uint8_t> leading(bytes.begin(), bytes.begin() + 20);  // IG Control cut short
  expectRejected(leading, RejectReason::PacketPastEnd);
  // A last packet claiming more bytes than are left.
  std::vector<std::uint8_t> unknownTail = bytes;
  unknownTail.insert(unknownTail.end(), {201, 40, 0, 0, 0, 0});
  expectRejected(unknownTail, RejectReason::PacketPastEnd);
  // One stray byte after the last packet: a header cannot fit.
  std::vector<std::uint8_t> stray = bytes;
  stray.push_back(EntityControl::kOpcode);
  expectRejected(stray, RejectReason::PacketPastEnd);
}

TEST(CigiDatagramDecoder, RejectsAKnownPacketOfTheWrongSize) {
  std::vector<std::uint8_t> bytes = hostMessage(ByteOrder::Big);
  const std::vector<std::size_t> starts = packetStarts(bytes);
  // Entity Control said to be 40 bytes, followed by what remains of it as an unknown tail: the
  // walk stays inside the datagram, so only the size check can catch it.
  bytes[starts[1] + 1] = 40;
  bytes[starts[1] + 40] = 201;
  bytes[starts[1] + 41] = 8;
  expectRejected(bytes, RejectReason::WrongPacketSize);
  // The leading IG Control at a size that is neither 3.3's 24 nor 3.0's 16.
  std::vector<std::uint8_t> lead = hostMessage(ByteOrder::Big);
  lead[1] = 32;
  expectRejected(lead, RejectReason::WrongPacketSize);
}

// Every prefix of a valid message: rejected, unless it ends exactly on a packet boundary (a
// shorter valid message). Each prefix sits in a buffer of exactly its length, so a read past it
// is caught by ASan in sanitizer builds.
TEST(CigiDatagramDecoder, TruncatedAtEveryLength) {
  for (const ByteOrder order : {ByteOrder::Big, ByteOrder::Little}) {
    const std::vector<std::uint8_t> full = hostMessage(order);
    const std::vector<std::size_t> starts = packetStarts(full);
    HostDatagramDecoder decoder;
    std::vector<HostPacket> packets;
    std::size_t accepted = 0;
    for (std::size_t length = 0; length < full.size(); ++length) {
      const std::vector<std::uint8_t> prefix(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(length));
      const DecodeResult r = decoder.decode(prefix, packets);
      const auto boundary = std::find(starts.begin() + 1, starts.end(), length);
      if (boundary != starts.end()) {
        ASSERT_TRUE(r.accepted()) << "length " << length;
        EXPECT_EQ(packets.size(), static_cast<std::size_t>(boundary - starts.begin()));
        ++accepted;
      } else {
        ASSERT_FALSE(r.accepted()) << "length " << length;
        EXPECT_EQ(*r.rejected, length < 2 ? RejectReason::TooShort : RejectReason::PacketPastEnd)
            << "length " << length;
        EXPECT_TRUE(packets.empty());
      }
    }
    EXPECT_EQ(accepted, starts.size() - 1);
    EXPECT_EQ(decoder.counters().rejectedTotal(), full.size() - accepted);
  }
}

TEST(CigiDatagramDecoder, ReasonsHaveNames) {
  for (std::size_t i = 0; i < kRejectReasonCount; ++i) {
    EXPECT_NE(toString(static_cast<RejectReason>(i)), "unknown reason") << i;
  }
}

}  // namespace
