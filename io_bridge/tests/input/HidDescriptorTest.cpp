// The HID parser against published descriptors of real sticks and gamepads, reports laid out as
// those devices send them, and malformed input that must be refused with a reason.
#include <io_bridge/HidReportDecoder.h>
#include <io_bridge/HidReportDescriptor.h>

#include "RealDescriptors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <vector>

namespace fieldcast::io {
namespace {

using namespace usages;

// Values of one decoded report by usage (first element of a usage wins, as the translator does).
std::map<Usage, std::int32_t> valuesOf(HidReportDecoder& d, std::span<const std::uint8_t> report) {
  const HidDecodeResult r = d.decode(report);
  EXPECT_EQ(r.status, HidDecodeStatus::Ok) << describe(r);
  std::map<Usage, std::int32_t> out;
  for (const HidValue& v : r.values) out.emplace(v.usage, v.value);
  return out;
}

// Final value per usage after translating one report into events.
std::map<Usage, std::int32_t> eventsOf(HidInputTranslator& t, std::span<const std::uint8_t> report) {
  std::vector<InputEvent> events;
  const HidDecodeResult r = t.translate(report, 1000, events);
  EXPECT_EQ(r.status, HidDecodeStatus::Ok) << describe(r);
  std::map<Usage, std::int32_t> out;
  for (const InputEvent& e : events) {
    if (e.type == InputEventType::Value) out[e.usage] = e.value;
  }
  if (!events.empty()) {
    EXPECT_EQ(events.back().type, InputEventType::Sync);
  }
  return out;
}

const HidField* fieldWith(const HidReportDescriptor& d, HidReportType type, Usage u) {
  for (const HidField& f : d.fields) {
    if (f.type == type && std::find(f.usages.begin(), f.usages.end(), u) != f.usages.end()) return &f;
  }
  return nullptr;
}

void put16(std::vector<std::uint8_t>& r, std::size_t at, std::uint16_t v) {
  r[at] = static_cast<std::uint8_t>(v & 0xFF);
  r[at + 1] = static_cast<std::uint8_t>(v >> 8);
}

TEST(HidDescriptor, RaptorMach2FlightStick) {
  const HidReportDescriptor d = parseHidReportDescriptor(testdata::kRaptorMach2);
  EXPECT_TRUE(d.usesReportIds);
  ASSERT_NE(d.report(HidReportType::Input, 1), nullptr);
  EXPECT_EQ(d.report(HidReportType::Input, 1)->wireBytes(true), 64u);
  EXPECT_EQ(d.report(HidReportType::Output, 0x58)->wireBytes(true), 64u);
  EXPECT_EQ(d.report(HidReportType::Feature, 0x59)->wireBytes(true), 129u);
  const HidField* hat = fieldWith(d, HidReportType::Input, kHatSwitch);
  ASSERT_NE(hat, nullptr);
  EXPECT_EQ(hat->bitOffset, 32u * 8u);  // bytes 33..34 of the report, as the kernel's fix says
  EXPECT_EQ(hat->logicalMax, 239);
  EXPECT_EQ(hat->physicalMax, 360);
  EXPECT_EQ(describeHidUnit(hat->unit, hat->unitExponent), "deg");
  ASSERT_EQ(d.collections.size(), 1u);
  EXPECT_EQ(d.collections[0].usage, makeUsage(1, 0x04));  // Joystick
  EXPECT_EQ(hat->application, makeUsage(1, 0x04));

  std::vector<std::uint8_t> report(64, 0);
  report[0] = 0x01;
  put16(report, 1, 2047);   // X full right
  put16(report, 3, 0);      // Y full forward
  put16(report, 9, 700);    // Z
  put16(report, 11, 512);   // Rz centred
  put16(report, 15, 1023);  // Slider
  report[17] = 0x01;        // button 1
  report[20] = 0x10;        // button 29 (bit 28)
  report[21] = 0x02;        // bit 33: a repeat of usage "Button 29" beyond the 29 usages
  put16(report, 33, 60);    // hat: the stick sends 30 per step, so 60 is East
  HidReportDecoder decoder(d);
  const auto v = valuesOf(decoder, report);
  EXPECT_EQ(v.at(kX), 2047);
  EXPECT_EQ(v.at(kY), 0);
  EXPECT_EQ(v.at(kZ), 700);
  EXPECT_EQ(v.at(kRz), 512);
  EXPECT_EQ(v.at(kSlider), 1023);
  EXPECT_EQ(v.at(button(1)), 1);
  EXPECT_EQ(v.at(button(29)), 1);

  HidInputTranslator t(d);
  const auto e = eventsOf(t, report);
  EXPECT_EQ(e.at(kHatSwitch), 2);  // East
  EXPECT_EQ(e.at(button(29)), 1);
  report[20] = 0x00;  // release button 29; its repeats stay set and must not hold it down
  EXPECT_EQ(eventsOf(t, report).at(button(29)), 0);
  put16(report, 33, 0xFF);  // beyond the logical range with a null state: centred
  EXPECT_EQ(eventsOf(t, report).at(kHatSwitch), kHatCentred);
}

TEST(HidDescriptor, ThrustmasterTcaYoke) {
  const HidReportDescriptor d = parseHidReportDescriptor(testdata::kTcaYokeBoeing);
  EXPECT_EQ(d.report(HidReportType::Input, 1)->wireBytes(true), 64u);
  EXPECT_EQ(d.report(HidReportType::Feature, 0xF2)->wireBytes(true), 64u);
  const HidField* axes = fieldWith(d, HidReportType::Input, kY);
  ASSERT_NE(axes, nullptr);
  EXPECT_EQ(axes->logicalMax, 65535);  // a 4-byte item, unsigned because the minimum is 0
  EXPECT_FALSE(axes->isSigned());
  EXPECT_EQ(axes->bitOffset, 24u);

  std::vector<std::uint8_t> report(64, 0);
  report[0] = 0x01;
  report[1] = 0x02 | 0x10;   // hat East; button 1 (bit 4)
  report[3] = 0x20;          // button 18 is bit 21
  put16(report, 4, 0xFFFF);  // Y: yoke pulled fully back
  put16(report, 6, 0x8000);  // X: centred
  put16(report, 14, 1234);   // Rz
  HidInputTranslator t(d);
  const auto e = eventsOf(t, report);
  EXPECT_EQ(e.at(kY), 65535);
  EXPECT_EQ(e.at(kX), 32768);
  EXPECT_EQ(e.at(kRz), 1234);
  EXPECT_EQ(e.at(kHatSwitch), 2);
  EXPECT_EQ(e.at(button(1)), 1);
  EXPECT_EQ(e.at(button(18)), 1);
  EXPECT_EQ(e.at(button(2)), 0);
}

TEST(HidDescriptor, SaitekForceFeedbackJoystick) {
  const HidReportDescriptor d = parseHidReportDescriptor(testdata::kSaitekFfbJoystick);
  EXPECT_EQ(d.report(HidReportType::Input, 1)->wireBytes(true), 7u);  // the zero-size constant adds nothing
  EXPECT_EQ(d.report(HidReportType::Input, 2)->wireBytes(true), 3u);
  // A PID duration: 16 bits, exponent 0xfd = -3 (not a nibble), unit seconds → milliseconds.
  const HidField* duration = fieldWith(d, HidReportType::Output, makeUsage(0x0F, 0x50));
  ASSERT_NE(duration, nullptr);
  EXPECT_EQ(duration->unitExponent, -3);
  EXPECT_EQ(describeHidUnit(duration->unit, duration->unitExponent), "s ×1e-3");
  EXPECT_EQ(duration->logicalMax, 65534);
  // A signed PID magnitude with a signed physical range.
  const HidField* magnitude = fieldWith(d, HidReportType::Output, makeUsage(0x0F, 0x70));
  ASSERT_NE(magnitude, nullptr);
  EXPECT_EQ(magnitude->logicalMin, -127);
  EXPECT_EQ(magnitude->physicalMin, -10000);
  // An array output (effect type selection) and vendor usage ranges.
  const HidField* effect = fieldWith(d, HidReportType::Output, makeUsage(0x0F, 0x79));
  ASSERT_NE(effect, nullptr);
  EXPECT_FALSE(effect->isVariable());
  EXPECT_EQ(effect->usages.size(), 3u);
  const HidField* vendor = fieldWith(d, HidReportType::Output, makeUsage(0xFF, 0x0320));
  ASSERT_NE(vendor, nullptr);
  EXPECT_EQ(vendor->usages.size(), 16u);
  EXPECT_EQ(d.collections.back().usage, makeUsage(0x0F, 0x90));

  const std::vector<std::uint8_t> report{0x01, 0x80, 0x7f, 0x00, 0xff, 0x05, 0x38};
  HidInputTranslator t(d);
  auto e = eventsOf(t, report);
  EXPECT_EQ(e.at(kX), 128);
  EXPECT_EQ(e.at(kY), 127);
  EXPECT_EQ(e.at(kRudder), 0);
  EXPECT_EQ(e.at(kThrottle), 255);
  EXPECT_EQ(e.at(button(1)), 1);
  EXPECT_EQ(e.at(button(3)), 1);
  EXPECT_EQ(e.at(button(12)), 1);
  EXPECT_EQ(e.at(kHatSwitch), 3);
  const std::vector<std::uint8_t> centred{0x01, 0x80, 0x7f, 0x00, 0xff, 0x05, 0xf8};
  e = eventsOf(t, centred);
  EXPECT_EQ(e.at(kHatSwitch), kHatCentred);
  EXPECT_EQ(e.size(), 1u);  // only what changed
}

TEST(HidDescriptor, AsusGamepadKeepsEachUsagesPage) {
  const HidReportDescriptor d = parseHidReportDescriptor(testdata::kAsusGamepad);
  EXPECT_EQ(d.report(HidReportType::Input, 1)->wireBytes(true), 9u);
  const HidField* buttons = fieldWith(d, HidReportType::Input, button(1));
  ASSERT_NE(buttons, nullptr);
  ASSERT_EQ(buttons->usages.size(), 11u);
  // The Consumer page declared after nine Button usages applies to the two usages after it only.
  EXPECT_EQ(buttons->usages[7], button(15));
  EXPECT_EQ(buttons->usages[8], button(13));
  EXPECT_EQ(buttons->usages[9], makeUsage(kConsumerPage, 0x224));   // AC Back
  EXPECT_EQ(buttons->usages[10], makeUsage(kConsumerPage, 0x223));  // AC Home

  const std::vector<std::uint8_t> report{0x01, 0x81, 0x24, 0x00, 0xff, 0x80, 0x7f, 0x10, 0xf0};
  HidInputTranslator t(d);
  const auto e = eventsOf(t, report);
  EXPECT_EQ(e.at(button(1)), 1);
  EXPECT_EQ(e.at(button(15)), 1);                       // bit 7
  EXPECT_EQ(e.at(makeUsage(kConsumerPage, 0x223)), 1);  // bit 10
  EXPECT_EQ(e.at(kHatSwitch), 2);
  EXPECT_EQ(e.at(kX), 0);
  EXPECT_EQ(e.at(kY), 255);
  EXPECT_EQ(e.at(kZ), 128);
  EXPECT_EQ(e.at(kRz), 127);
  EXPECT_EQ(e.at(kBrake), 0x10);
  EXPECT_EQ(e.at(kAccelerator), 0xf0);
}

TEST(HidDescriptor, DualShock4Gamepad) {
  const HidReportDescriptor d = parseHidReportDescriptor(testdata::kDualShock4);
  // The sizes Chromium's test asserts for this descriptor: 63/31/63 data bytes.
  EXPECT_EQ(d.report(HidReportType::Input, 1)->wireBytes(false), 63u);
  EXPECT_EQ(d.report(HidReportType::Output, 5)->wireBytes(false), 31u);
  EXPECT_EQ(d.maxInputReportBytes(), 64u);
  std::size_t mostFeature = 0;
  for (const HidReportInfo& r : d.reports) {
    if (r.type == HidReportType::Feature) mostFeature = std::max(mostFeature, r.wireBytes(false));
  }
  EXPECT_EQ(mostFeature, 63u);

  // Report 1 as the DS4 sends it: sticks, d-pad N + Cross, L2 pressed, counter 2, L2 fully in.
  std::vector<std::uint8_t> report(64, 0);
  const std::uint8_t head[] = {0x01, 0x00, 0xff, 0x7f, 0x80, 0x20, 0x04, 0x08, 0xff, 0x00};
  std::copy(std::begin(head), std::end(head), report.begin());
  HidReportDecoder decoder(d);
  const auto v = valuesOf(decoder, report);
  EXPECT_EQ(v.at(kX), 0);
  EXPECT_EQ(v.at(kY), 255);
  EXPECT_EQ(v.at(kZ), 127);
  EXPECT_EQ(v.at(kRz), 128);
  EXPECT_EQ(v.at(kHatSwitch), 0);
  EXPECT_EQ(v.at(button(1)), 0);                // Square
  EXPECT_EQ(v.at(button(2)), 1);                // Cross
  EXPECT_EQ(v.at(button(7)), 1);                // L2 (digital)
  EXPECT_EQ(v.at(makeUsage(0xFF00, 0x20)), 2);  // frame counter
  EXPECT_EQ(v.at(kRx), 255);                    // L2 analog
  EXPECT_EQ(v.at(kRy), 0);
  // Idle report: d-pad released (8 is outside 0..7 and the field has a null state).
  report[5] = 0x08;
  HidInputTranslator t(d);
  EXPECT_EQ(eventsOf(t, report).at(kHatSwitch), kHatCentred);
}

TEST(HidDescriptor, SignedFieldsAndPushPop) {
  const std::uint8_t desc[] = {0x05, 0x01, 0x09, 0x04, 0xa1, 0x01,              // Joystick application
                               0x15, 0x81, 0x25, 0x7f,                          // Logical -127..127
                               0xa4,                                            // Push
                               0x16, 0x00, 0x80, 0x26, 0xff, 0x7f,              // Logical -32768..32767
                               0x75, 0x10, 0x95, 0x01, 0x09, 0x30, 0x81, 0x02,  // X: 16-bit signed
                               0xb4,                                            // Pop: back to -127..127, no size/count
                               0x75, 0x08, 0x95, 0x01, 0x09, 0x31, 0x81, 0x02,  // Y: 8-bit signed
                               0x75, 0x03, 0x81, 0x03,                          // 3 bits of padding
                               0x75, 0x05, 0x15, 0x00, 0x25, 0x1f, 0x09, 0x32, 0x81, 0x02,  // Z: 5 bits unsigned
                               0xc0};
  const HidReportDescriptor d = parseHidReportDescriptor(desc);
  EXPECT_FALSE(d.usesReportIds);
  ASSERT_EQ(d.fields.size(), 3u);
  EXPECT_EQ(d.fields[0].logicalMin, -32768);
  EXPECT_EQ(d.fields[1].logicalMin, -127);
  EXPECT_EQ(d.fields[2].bitOffset, 27u);
  HidReportDecoder decoder(d);
  const std::vector<std::uint8_t> report{0x85, 0xff, 0x85, 0xf8};  // X -123, Y -123, Z 31
  const auto v = valuesOf(decoder, report);
  EXPECT_EQ(v.at(kX), -123);
  EXPECT_EQ(v.at(kY), -123);
  EXPECT_EQ(v.at(kZ), 31);
}

TEST(HidDescriptor, ArraySelectionsPressAndRelease) {
  // A panel reporting up to two pressed buttons out of eight as an array (like a keyboard).
  const std::uint8_t desc[] = {0x05, 0x01, 0x09, 0x04, 0xa1, 0x01, 0x05, 0x09, 0x19, 0x01, 0x29, 0x08,
                               0x15, 0x01, 0x25, 0x08, 0x75, 0x08, 0x95, 0x02, 0x81, 0x00, 0xc0};
  HidInputTranslator t(parseHidReportDescriptor(desc));
  EXPECT_EQ(t.controls().size(), 8u);
  EXPECT_EQ(t.controls()[2].kind, ControlKind::Button);
  auto e = eventsOf(t, std::vector<std::uint8_t>{3, 0});  // 0 is outside 1..8: no selection
  EXPECT_EQ(e, (std::map<Usage, std::int32_t>{{button(3), 1}}));
  e = eventsOf(t, std::vector<std::uint8_t>{3, 5});
  EXPECT_EQ(e, (std::map<Usage, std::int32_t>{{button(5), 1}}));
  e = eventsOf(t, std::vector<std::uint8_t>{5, 0});
  EXPECT_EQ(e, (std::map<Usage, std::int32_t>{{button(3), 0}}));
  e = eventsOf(t, std::vector<std::uint8_t>{0, 0});
  EXPECT_EQ(e, (std::map<Usage, std::int32_t>{{button(5), 0}}));
}

TEST(HidDescriptor, ExtractMatchesBitByBitReference) {
  // The reference: assemble the value one bit at a time.
  std::vector<std::uint8_t> data(16);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(i * 37 + 11);
  for (std::uint32_t size = 1; size <= 32; ++size) {
    for (std::uint32_t offset = 0; offset + size <= 96; offset += 5) {
      std::uint64_t ref = 0;
      for (std::uint32_t b = 0; b < size; ++b) {
        const std::uint32_t bit = offset + b;
        ref |= std::uint64_t{(data[bit / 8] >> (bit % 8)) & 1u} << b;
      }
      const auto u = HidReportDecoder::extract(data, offset, size, false);
      EXPECT_EQ(static_cast<std::uint32_t>(u), static_cast<std::uint32_t>(ref)) << size << "@" << offset;
      const bool negative = (ref >> (size - 1)) & 1u;
      const std::int64_t sref =
          negative ? static_cast<std::int64_t>(ref) - (std::int64_t{1} << size) : static_cast<std::int64_t>(ref);
      EXPECT_EQ(HidReportDecoder::extract(data, offset, size, true), static_cast<std::int32_t>(sref));
    }
  }
}

struct Malformed {
  const char* what;
  std::vector<std::uint8_t> bytes;
  const char* reason;  // a piece of the message
};

TEST(HidDescriptor, MalformedDescriptorsAreRejectedWithAReason) {
  const std::vector<Malformed> cases{
      {"empty", {}, "empty"},
      {"truncated item", {0x05, 0x01, 0x26, 0xff}, "needs 2 data bytes"},
      {"end without collection", {0xc0}, "End Collection without"},
      {"unclosed collection", {0x05, 0x01, 0x09, 0x04, 0xa1, 0x01}, "not closed"},
      {"pop empty stack", {0xb4}, "Pop with an empty"},
      {"report id 0", {0x85, 0x00}, "Report ID 0"},
      {"logical max below min",
       {0x09, 0x30, 0x15, 0x0a, 0x25, 0x05, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02},
       "Logical Maximum 5"},
      {"reserved item type", {0x0c}, "reserved item type"},
      {"report size too big", {0x76, 0x2c, 0x01}, "Report Size 300"},
      {"report count too big", {0x96, 0xff, 0xff}, "Report Count 65535"},
      {"usage min above max", {0x19, 0x05, 0x29, 0x03}, "Usage Minimum 0x5 > Usage Maximum 0x3"},
      {"usage max alone", {0x29, 0x03}, "Usage Maximum without"},
      {"usage min alone", {0x19, 0x01, 0x75, 0x01, 0x95, 0x01, 0x81, 0x02}, "Usage Minimum without"},
      {"report too long", {0x09, 0x30, 0x76, 0x00, 0x01, 0x96, 0x00, 0x30, 0x81, 0x02}, "grows beyond"},
      {"unknown global", {0xc4}, "unknown Global item tag"},
      {"unnumbered main with report ids",
       {0x09, 0x30, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02, 0x85, 0x01, 0x09, 0x31, 0x81, 0x02},
       "belongs to no report"},
      {"long item cut", {0xfe, 0x05, 0x00, 0x01}, "long item data"},
      {"nested delimiter", {0xa9, 0x01, 0xa9, 0x01}, "nested Delimiter"},
  };
  for (const Malformed& c : cases) {
    try {
      (void)parseHidReportDescriptor(c.bytes);
      ADD_FAILURE() << c.what << ": accepted";
    } catch (const HidDescriptorError& e) {
      EXPECT_NE(std::string(e.what()).find(c.reason), std::string::npos) << c.what << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("byte "), std::string::npos) << c.what;
    }
  }
}

// One-byte array items, each choosing from 12,288 keys (Usage Minimum 0 .. Maximum 0x2FFF): the
// largest item Linux accepts. `items` of them in one report.
std::vector<std::uint8_t> wideArrayItems(int items) {
  std::vector<std::uint8_t> d{0x05, 0x07, 0x15, 0x00, 0x26, 0xff, 0x2f, 0x75, 0x08, 0x95, 0x01};
  for (int i = 0; i < items; ++i) d.insert(d.end(), {0x19, 0x00, 0x2a, 0xff, 0x2f, 0x81, 0x00});
  return d;
}

TEST(HidDescriptor, UsagesOfTheWholeDescriptorAreBounded) {
  // One such item parses (the kernel's own limit); two would name 24,576 usages in 22 bytes, and
  // a 2 KB descriptor of them millions, so the whole descriptor is bounded too.
  const HidReportDescriptor one = parseHidReportDescriptor(wideArrayItems(1));
  ASSERT_EQ(one.fields.size(), 1u);
  EXPECT_EQ(one.fields[0].usages.size(), 12288u);
  try {
    (void)parseHidReportDescriptor(wideArrayItems(2));
    ADD_FAILURE() << "24,576 usages accepted";
  } catch (const HidDescriptorError& e) {
    EXPECT_NE(std::string(e.what()).find("more than 16384 usages"), std::string::npos) << e.what();
  }
}

TEST(HidDescriptor, DescriptorsWithoutInputFieldsParseAsTheKernelReadsThem) {
  // Whether a device has inputs is the consumer's question, not the parser's: the kernel accepts
  // these (an unknown main tag is skipped; output-only devices exist), so the parser does too.
  // The hidraw and USB sources and `fieldcast-stick descriptor` refuse them for want of inputs.
  const HidReportDescriptor nothing = parseHidReportDescriptor(std::vector<std::uint8_t>{0x00});
  EXPECT_TRUE(nothing.fields.empty());
  EXPECT_TRUE(nothing.reports.empty());
  EXPECT_TRUE(HidInputTranslator(nothing).controls().empty());
  const HidReportDescriptor leds = parseHidReportDescriptor(
      std::vector<std::uint8_t>{0x05, 0x08, 0x09, 0x01, 0xa1, 0x01, 0x09, 0x4b, 0x15, 0x00, 0x25, 0x01,
                                0x75, 0x01, 0x95, 0x01, 0x91, 0x02, 0x95, 0x07, 0x91, 0x03, 0xc0});
  ASSERT_EQ(leds.fields.size(), 1u);
  EXPECT_EQ(leds.fields[0].type, HidReportType::Output);
  EXPECT_EQ(leds.maxInputReportBytes(), 0u);
  EXPECT_TRUE(HidInputTranslator(leds).controls().empty());
}

TEST(HidDescriptor, ShortAndUnknownReportsAreRejectedWithAReason) {
  HidReportDecoder decoder(parseHidReportDescriptor(testdata::kRaptorMach2));
  const std::vector<std::uint8_t> shortReport(20, 0x01);
  const HidDecodeResult r = decoder.decode(shortReport);
  EXPECT_EQ(r.status, HidDecodeStatus::ShortReport);
  EXPECT_EQ(describe(r), "report 1: 20 bytes, the descriptor declares 64");
  const std::vector<std::uint8_t> unknown{0x09, 0, 0, 0};
  EXPECT_EQ(decoder.decode(unknown).status, HidDecodeStatus::UnknownReport);
  EXPECT_EQ(describe(decoder.decode(unknown)), "report 9: not an Input report of this descriptor");
  EXPECT_EQ(decoder.decode({}).status, HidDecodeStatus::Empty);
  // Output and Feature report IDs are not Input reports.
  const std::vector<std::uint8_t> output(64, 0x58);
  EXPECT_EQ(decoder.decode(output).status, HidDecodeStatus::UnknownReport);
  // A longer report is accepted: devices pad.
  std::vector<std::uint8_t> padded(80, 0);
  padded[0] = 0x01;
  EXPECT_EQ(decoder.decode(padded).status, HidDecodeStatus::Ok);
}

TEST(HidDescriptor, TranslatorDescribesTheControls) {
  HidInputTranslator t(parseHidReportDescriptor(testdata::kSaitekFfbJoystick));
  const auto& c = t.controls();
  auto find = [&](Usage u) {
    return std::find_if(c.begin(), c.end(), [&](const ControlInfo& i) { return i.usage == u; });
  };
  ASSERT_NE(find(kThrottle), c.end());
  EXPECT_EQ(find(kThrottle)->max, 255);
  ASSERT_NE(find(kHatSwitch), c.end());
  EXPECT_EQ(find(kHatSwitch)->kind, ControlKind::Hat);
  ASSERT_NE(find(button(12)), c.end());
  EXPECT_EQ(find(button(12))->kind, ControlKind::Button);
  EXPECT_EQ(find(button(13)), c.end());
}

}  // namespace
}  // namespace fieldcast::io
