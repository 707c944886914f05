// Message builders: the leading packet first with the magic in the chosen order, packets
// appended back to back, the size bound respected.
#include <io_bridge/cigi/MessageBuilder.h>

#include "SamplePackets.h"

#include <gtest/gtest.h>

namespace {

using namespace fieldcast::io::cigi;
namespace td = fieldcast::io::cigi::testdata;

TEST(CigiMessageBuilder, StartsWithTheLeadingPacketInTheChosenOrder) {
  HostMessageBuilder native;
  native.start(td::sampleIgControl());
  ASSERT_EQ(native.bytes().size(), IgControl::kSize);
  EXPECT_EQ(native.bytes()[0], IgControl::kOpcode);
  EXPECT_EQ(native.byteOrder(), nativeByteOrder());

  HostMessageBuilder swapped(swappedByteOrder());
  swapped.start(td::sampleIgControl());
  // Magic bytes 6-7: 80 00 from a big-endian sender, 00 80 from a little-endian one.
  const bool bigSender = swappedByteOrder() == ByteOrder::Big;
  EXPECT_EQ(swapped.bytes()[6], bigSender ? 0x80 : 0x00);
  EXPECT_EQ(swapped.bytes()[7], bigSender ? 0x00 : 0x80);
  EXPECT_EQ(native.bytes()[6], bigSender ? 0x00 : 0x80);
}

TEST(CigiMessageBuilder, AppendsPacketsBackToBack) {
  IgMessageBuilder ig;
  ig.start(td::sampleStartOfFrame());
  ASSERT_TRUE(ig.add(td::sampleHatHotResponse()));
  ASSERT_TRUE(ig.add(td::sampleLosExtendedResponse()));
  const auto bytes = ig.bytes();
  ASSERT_EQ(bytes.size(), StartOfFrame::kSize + HatHotResponse::kSize + LosExtendedResponse::kSize);
  EXPECT_EQ(bytes[0], StartOfFrame::kOpcode);
  EXPECT_EQ(bytes[StartOfFrame::kSize], HatHotResponse::kOpcode);
  EXPECT_EQ(bytes[StartOfFrame::kSize + HatHotResponse::kSize], LosExtendedResponse::kOpcode);
  // start() begins a new message.
  ig.start(td::sampleStartOfFrame());
  EXPECT_EQ(ig.bytes().size(), StartOfFrame::kSize);
}

TEST(CigiMessageBuilder, RefusesPacketsBeforeStartAndBeyondTheBound) {
  HostMessageBuilder host(nativeByteOrder(), IgControl::kSize + EntityControl::kSize + 10);
  EXPECT_FALSE(host.add(td::sampleEntityControl())) << "no IG Control yet";
  EXPECT_TRUE(host.bytes().empty());
  host.start(td::sampleIgControl());
  EXPECT_TRUE(host.add(td::sampleEntityControl()));
  EXPECT_FALSE(host.add(td::sampleEntityControl())) << "would exceed the bound";
  EXPECT_EQ(host.bytes().size(), IgControl::kSize + EntityControl::kSize);
}

}  // namespace
