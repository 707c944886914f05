#include <fieldcast/Field.h>

#include <gtest/gtest.h>

namespace fieldcast {
namespace {

TEST(Field, RowCountsSplitTheRaster) {
  EXPECT_EQ(fieldRowCount(FieldParity::Top, 486), 243);
  EXPECT_EQ(fieldRowCount(FieldParity::Bottom, 486), 243);
  EXPECT_EQ(fieldRowCount(FieldParity::Top, 5), 3);
  EXPECT_EQ(fieldRowCount(FieldParity::Bottom, 5), 2);
  EXPECT_EQ(fieldRowCount(FieldParity::Progressive, 1080), 1080);
}

TEST(Field, RasterRowsInterleave) {
  EXPECT_EQ(rasterRow(FieldParity::Top, 0), 0);
  EXPECT_EQ(rasterRow(FieldParity::Top, 121), 242);
  EXPECT_EQ(rasterRow(FieldParity::Bottom, 0), 1);
  EXPECT_EQ(rasterRow(FieldParity::Bottom, 242), 485);
  EXPECT_EQ(rasterRow(FieldParity::Progressive, 17), 17);
}

TEST(Field, ParityAlternatesInTheConfiguredOrder) {
  EXPECT_EQ(parityOfField(0, ScanMode::Interlaced, FieldOrder::TopFirst), FieldParity::Top);
  EXPECT_EQ(parityOfField(1, ScanMode::Interlaced, FieldOrder::TopFirst), FieldParity::Bottom);
  EXPECT_EQ(parityOfField(0, ScanMode::Interlaced, FieldOrder::BottomFirst), FieldParity::Bottom);
  EXPECT_EQ(parityOfField(1, ScanMode::Interlaced, FieldOrder::BottomFirst), FieldParity::Top);
  EXPECT_EQ(parityOfField(1001, ScanMode::Interlaced, FieldOrder::BottomFirst), FieldParity::Top);
  EXPECT_EQ(parityOfField(7, ScanMode::Progressive, FieldOrder::TopFirst), FieldParity::Progressive);
}

}  // namespace
}  // namespace fieldcast
