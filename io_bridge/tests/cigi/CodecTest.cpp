// Single-packet encode/decode: every packet round-trips in both byte orders with every field
// set, and the byte layout of IG Control, Entity Control and Start of Frame matches byte strings
// written by hand from the CIGI 3.3 ICD (not produced by our encoder).
#include <io_bridge/cigi/Codec.h>

#include "SamplePackets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <tuple>
#include <type_traits>
#include <vector>

namespace {

using namespace fieldcast::io::cigi;
namespace td = fieldcast::io::cigi::testdata;

/// The sample of packet type P.
template <class P>
P samplePacket() {
  return std::get<P>(std::tuple{
      td::sampleIgControl(), td::sampleEntityControl(), td::sampleRateControl(), td::sampleCelestialSphereControl(),
      td::sampleAtmosphereControl(), td::sampleViewControl(), td::sampleViewDefinition(), td::sampleHatHotRequest(),
      td::sampleLosSegmentRequest(), td::sampleLosVectorRequest(), td::sampleStartOfFrame(), td::sampleHatHotResponse(),
      td::sampleHatHotExtendedResponse(), td::sampleLosResponse(), td::sampleLosExtendedResponse()});
}

template <class P>
std::array<std::uint8_t, P::kSize> encoded(const P& p, ByteOrder order) {
  std::array<std::uint8_t, P::kSize> bytes{};
  encode(p, order, std::span<std::uint8_t, P::kSize>(bytes));
  return bytes;
}

template <class P>
P decoded(const std::array<std::uint8_t, P::kSize>& bytes, ByteOrder order) {
  P p{};
  decode(std::span<const std::uint8_t, P::kSize>(bytes), order, p);
  return p;
}

template <class P>
class CigiPacketRoundTrip : public ::testing::Test {};
using AllPackets =
    ::testing::Types<IgControl, EntityControl, RateControl, CelestialSphereControl, AtmosphereControl, ViewControl,
                     ViewDefinition, HatHotRequest, LosSegmentRequest, LosVectorRequest, StartOfFrame, HatHotResponse,
                     HatHotExtendedResponse, LosResponse, LosExtendedResponse>;
TYPED_TEST_SUITE(CigiPacketRoundTrip, AllPackets);

// The sample sets most fields to non-default values; the bits it leaves at their default are
// covered by EveryFieldBitSurvives below.
TYPED_TEST(CigiPacketRoundTrip, EveryFieldSurvivesBothByteOrders) {
  const TypeParam sample = samplePacket<TypeParam>();
  ASSERT_FALSE(sample == TypeParam{}) << "the sample must set fields";
  for (const ByteOrder order : {ByteOrder::Big, ByteOrder::Little}) {
    const auto bytes = encoded(sample, order);
    EXPECT_EQ(bytes[0], TypeParam::kOpcode);
    EXPECT_EQ(bytes[1], TypeParam::kSize);
    EXPECT_EQ(decoded<TypeParam>(bytes, order), sample) << "order " << (order == ByteOrder::Big ? "big" : "little");
  }
}

// The two orders hold the same bytes field by field, reversed within each multi-byte field: the
// big-endian encoding read as little-endian is not the sample (so the order is really applied).
TYPED_TEST(CigiPacketRoundTrip, TheOrderIsApplied) {
  const TypeParam sample = samplePacket<TypeParam>();
  const auto big = encoded(sample, ByteOrder::Big);
  const auto little = encoded(sample, ByteOrder::Little);
  EXPECT_NE(big, little);
  EXPECT_FALSE(decoded<TypeParam>(big, ByteOrder::Little) == sample);
}

// The default packet encodes to zeros outside the header and the fields that cannot be zero
// (version, magic, minor version, alpha): reserved bytes stay zero.
TEST(CigiPacketLayout, ReservedBytesAreZero) {
  const auto bytes = encoded(td::sampleLosVectorRequest(), ByteOrder::Big);
  EXPECT_EQ(bytes[53], 0);
  EXPECT_EQ(bytes[54], 0);
  EXPECT_EQ(bytes[55], 0);
  const auto sof = encoded(td::sampleStartOfFrame(), ByteOrder::Big);
  for (std::size_t i = 20; i < 24; ++i) EXPECT_EQ(sof[i], 0) << "byte " << i;
}

/// Bits of one byte that belong to no field, per the ICD: reserved bits (zero on the wire) or
/// constants the encoder writes (major version, minor version nibble).
struct NonFieldBits {
  std::size_t offset;
  std::uint8_t fieldMask;  ///< the bits of this byte that are fields
  std::uint8_t constant;   ///< the value of the other bits
};

/// Every byte of P that is not wholly a field, written by hand from the CIGI 3.3 ICD (bytes 0–1,
/// id and size, and the leading packets' byte-swap magic are handled by the test).
template <class P>
std::vector<NonFieldBits> nonFieldBits() {
  if constexpr (std::is_same_v<P, IgControl>)
    return {{2, 0x00, 3}, {4, 0x0F, 0x30}, {5, 0, 0}, {20, 0, 0}, {21, 0, 0}, {22, 0, 0}, {23, 0, 0}};
  if constexpr (std::is_same_v<P, EntityControl>) return {{4, 0x7F, 0}, {5, 0x1F, 0}, {7, 0, 0}};
  if constexpr (std::is_same_v<P, RateControl>) return {{5, 0x03, 0}, {6, 0, 0}, {7, 0, 0}};
  if constexpr (std::is_same_v<P, CelestialSphereControl>) return {{4, 0x1F, 0}, {5, 0, 0}, {6, 0, 0}, {7, 0, 0}};
  if constexpr (std::is_same_v<P, AtmosphereControl>)
    return {{2, 0x01, 0}, {28, 0, 0}, {29, 0, 0}, {30, 0, 0}, {31, 0, 0}};
  if constexpr (std::is_same_v<P, ViewControl>) return {{5, 0x3F, 0}};
  if constexpr (std::is_same_v<P, ViewDefinition>) return {{7, 0, 0}};
  if constexpr (std::is_same_v<P, HatHotRequest>) return {{4, 0x07, 0}};
  if constexpr (std::is_same_v<P, LosSegmentRequest>) return {{4, 0x1F, 0}, {61, 0, 0}};
  if constexpr (std::is_same_v<P, LosVectorRequest>) return {{4, 0x07, 0}, {53, 0, 0}, {54, 0, 0}, {55, 0, 0}};
  if constexpr (std::is_same_v<P, StartOfFrame>)
    return {{2, 0x00, 3}, {5, 0x0F, 0x30}, {20, 0, 0}, {21, 0, 0}, {22, 0, 0}, {23, 0, 0}};
  if constexpr (std::is_same_v<P, HatHotResponse>) return {{4, 0xF3, 0}, {5, 0, 0}, {6, 0, 0}, {7, 0, 0}};
  if constexpr (std::is_same_v<P, HatHotExtendedResponse>)
    return {{4, 0xF1, 0}, {5, 0, 0}, {6, 0, 0}, {7, 0, 0}, {36, 0, 0}, {37, 0, 0}, {38, 0, 0}, {39, 0, 0}};
  if constexpr (std::is_same_v<P, LosResponse>) return {{4, 0xF7, 0}};
  if constexpr (std::is_same_v<P, LosExtendedResponse>) return {};
}

// Random wire bytes with every field bit random and every other bit as the ICD has it: decode
// then encode must give the same bytes back. A field bit that decode or encode drops, moves or
// shares with another field changes the bytes.
TYPED_TEST(CigiPacketRoundTrip, EveryFieldBitSurvives) {
  std::mt19937 random(19);
  const std::vector<NonFieldBits> nonField = nonFieldBits<TypeParam>();
  for (const ByteOrder order : {ByteOrder::Big, ByteOrder::Little}) {
    const auto reference = encoded(TypeParam{}, order);  // header and, for leading packets, the magic
    for (int trial = 0; trial < 200; ++trial) {
      std::array<std::uint8_t, TypeParam::kSize> wire{};
      for (std::size_t i = 2; i < wire.size(); ++i) wire[i] = static_cast<std::uint8_t>(random());
      for (const NonFieldBits& b : nonField) {
        wire[b.offset] = static_cast<std::uint8_t>((wire[b.offset] & b.fieldMask) | b.constant);
      }
      wire[0] = reference[0];
      wire[1] = reference[1];
      if constexpr (std::is_same_v<TypeParam, IgControl> || std::is_same_v<TypeParam, StartOfFrame>) {
        wire[6] = reference[6];
        wire[7] = reference[7];
      }
      const auto again = encoded(decoded<TypeParam>(wire, order), order);
      for (std::size_t i = 0; i < wire.size(); ++i) {
        ASSERT_EQ(again[i], wire[i]) << "byte " << i << ", trial " << trial << ", "
                                     << (order == ByteOrder::Big ? "big" : "little") << "-endian";
      }
    }
  }
}

// ---- Byte layouts written by hand from the ICD ------------------------------------------------

// IG Control: id 1, size 24, major 3, database 7, byte 4 = IG mode Operate (1) | timestamp valid
// (0x04) | extrapolation (0x08) | minor version 3 << 4 = 0x3D, reserved, magic 0x8000, host frame
// 0x01020304, timestamp 123456789 = 0x075BCD15, last IG frame 987654 = 0x000F1206, 4 reserved.
const std::vector<std::uint8_t> kIgControlBig = {0x01, 0x18, 0x03, 0x07, 0x3D, 0x00, 0x80, 0x00,  //
                                                 0x01, 0x02, 0x03, 0x04, 0x07, 0x5B, 0xCD, 0x15,  //
                                                 0x00, 0x0F, 0x12, 0x06, 0x00, 0x00, 0x00, 0x00};
// The same packet from a little-endian sender: each multi-byte field reversed, magic 0x0080.
const std::vector<std::uint8_t> kIgControlLittle = {0x01, 0x18, 0x03, 0x07, 0x3D, 0x00, 0x00, 0x80,  //
                                                    0x04, 0x03, 0x02, 0x01, 0x15, 0xCD, 0x5B, 0x07,  //
                                                    0x06, 0x12, 0x0F, 0x00, 0x00, 0x00, 0x00, 0x00};

// Entity Control: id 2, size 48, entity 42; byte 4 = Active (1) | attached (0x04) | collision
// (0x08) | inherit alpha (0x10) | conformal clamp (2 << 5 = 0x40) = 0x5D; byte 5 = backward
// (0x01) | continuous (0x02) | Play (2 << 2 = 0x08) | extrapolation (0x10) = 0x1B; alpha 200,
// reserved, type 1234 = 0x04D2, parent 7, roll 1.5f = 0x3FC00000, pitch -2.25f = 0xC0100000,
// yaw 271.75f = 0x4387E000, lat 37.625 = 0x4042D00000000000, lon -122.375 = 0xC05E980000000000,
// alt 1234.5 = 0x40934A0000000000.
const std::vector<std::uint8_t> kEntityControlBig = {0x02, 0x30, 0x00, 0x2A, 0x5D, 0x1B, 0xC8, 0x00,  //
                                                     0x04, 0xD2, 0x00, 0x07, 0x3F, 0xC0, 0x00, 0x00,  //
                                                     0xC0, 0x10, 0x00, 0x00, 0x43, 0x87, 0xE0, 0x00,  //
                                                     0x40, 0x42, 0xD0, 0x00, 0x00, 0x00, 0x00, 0x00,  //
                                                     0xC0, 0x5E, 0x98, 0x00, 0x00, 0x00, 0x00, 0x00,  //
                                                     0x40, 0x93, 0x4A, 0x00, 0x00, 0x00, 0x00, 0x00};

// Start of Frame: id 101, size 24, major 3, database -7 (0xF9), IG status 2, byte 5 = Operate (1)
// | timestamp valid (0x04) | host-defined ERM (0x08) | minor 3 << 4 = 0x3D, magic, IG frame
// 0x12345678, timestamp 4000000000 = 0xEE6B2800, last host frame 0x01020304, 4 reserved.
const std::vector<std::uint8_t> kStartOfFrameBig = {0x65, 0x18, 0x03, 0xF9, 0x02, 0x3D, 0x80, 0x00,  //
                                                    0x12, 0x34, 0x56, 0x78, 0xEE, 0x6B, 0x28, 0x00,  //
                                                    0x01, 0x02, 0x03, 0x04, 0x00, 0x00, 0x00, 0x00};
const std::vector<std::uint8_t> kStartOfFrameLittle = {0x65, 0x18, 0x03, 0xF9, 0x02, 0x3D, 0x00, 0x80,  //
                                                       0x78, 0x56, 0x34, 0x12, 0x00, 0x28, 0x6B, 0xEE,  //
                                                       0x04, 0x03, 0x02, 0x01, 0x00, 0x00, 0x00, 0x00};

template <class P>
std::vector<std::uint8_t> asVector(const std::array<std::uint8_t, P::kSize>& a) {
  return {a.begin(), a.end()};
}

template <class P>
std::array<std::uint8_t, P::kSize> asArray(const std::vector<std::uint8_t>& v) {
  std::array<std::uint8_t, P::kSize> a{};
  EXPECT_EQ(v.size(), a.size());
  std::copy_n(v.begin(), std::min(v.size(), a.size()), a.begin());
  return a;
}

TEST(CigiPacketLayout, IgControlMatchesTheIcd) {
  EXPECT_EQ(asVector<IgControl>(encoded(td::sampleIgControl(), ByteOrder::Big)), kIgControlBig);
  EXPECT_EQ(asVector<IgControl>(encoded(td::sampleIgControl(), ByteOrder::Little)), kIgControlLittle);
  EXPECT_EQ(decoded<IgControl>(asArray<IgControl>(kIgControlBig), ByteOrder::Big), td::sampleIgControl());
  EXPECT_EQ(decoded<IgControl>(asArray<IgControl>(kIgControlLittle), ByteOrder::Little), td::sampleIgControl());
}

TEST(CigiPacketLayout, EntityControlMatchesTheIcd) {
  EXPECT_EQ(asVector<EntityControl>(encoded(td::sampleEntityControl(), ByteOrder::Big)), kEntityControlBig);
  EXPECT_EQ(decoded<EntityControl>(asArray<EntityControl>(kEntityControlBig), ByteOrder::Big),
            td::sampleEntityControl());
}

TEST(CigiPacketLayout, StartOfFrameMatchesTheIcd) {
  EXPECT_EQ(asVector<StartOfFrame>(encoded(td::sampleStartOfFrame(), ByteOrder::Big)), kStartOfFrameBig);
  EXPECT_EQ(asVector<StartOfFrame>(encoded(td::sampleStartOfFrame(), ByteOrder::Little)), kStartOfFrameLittle);
  EXPECT_EQ(decoded<StartOfFrame>(asArray<StartOfFrame>(kStartOfFrameLittle), ByteOrder::Little),
            td::sampleStartOfFrame());
}

// Bit fields decode the raw value even where the enum names none (a 2-bit IG mode of 3).
TEST(CigiPacketLayout, IgModeTakesEveryTwoBitValue) {
  auto bytes = asArray<IgControl>(kIgControlBig);
  bytes[4] = static_cast<std::uint8_t>((bytes[4] & 0xFC) | 0x03);
  EXPECT_EQ(decoded<IgControl>(bytes, ByteOrder::Big).igMode, IgMode::OfflineMaintenance);
  bytes[4] = static_cast<std::uint8_t>(bytes[4] & 0xFC);
  EXPECT_EQ(decoded<IgControl>(bytes, ByteOrder::Big).igMode, IgMode::ResetStandby);
}

}  // namespace
