#pragma once
// Our own parser of USB HID report descriptors (Device Class Definition for HID 1.11, §6.2.2):
// usage pages, collections, report IDs, logical/physical ranges, units and exponents, signed
// fields, arrays and variables, padding, push/pop. It follows the Linux HID core where the spec
// is loose (signedness of maxima, usage-page concatenation at the main item, 4-bit unit
// exponents) so a descriptor the kernel accepts is read the way the kernel reads it.
//
// Not RT-safe: parse once when a device is opened, then decode with HidReportDecoder.

#include <io_bridge/InputEvent.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace fieldcast::io {

/// The three kinds of report a descriptor declares.
enum class HidReportType : std::uint8_t { Input, Output, Feature };

/// Bits of the Input/Output/Feature main item data (HID 1.11 §6.2.2.5).
namespace hidflags {
constexpr std::uint32_t kConstant = 1u << 0;  ///< else Data
constexpr std::uint32_t kVariable = 1u << 1;  ///< else Array
constexpr std::uint32_t kRelative = 1u << 2;  ///< else Absolute
constexpr std::uint32_t kWrap = 1u << 3;
constexpr std::uint32_t kNonLinear = 1u << 4;
constexpr std::uint32_t kNoPreferred = 1u << 5;
constexpr std::uint32_t kNullState = 1u << 6;
constexpr std::uint32_t kBufferedBytes = 1u << 8;
}  // namespace hidflags

/// One data field of a report: `count` elements of `bitSize` bits from `bitOffset`.
struct HidField {
  HidReportType type = HidReportType::Input;
  std::uint8_t reportId = 0;    ///< 0 when the descriptor uses no report IDs
  std::uint32_t bitOffset = 0;  ///< from the first data byte (after the report ID byte, if any)
  std::uint32_t bitSize = 0;    ///< Report Size
  std::uint32_t count = 0;      ///< Report Count
  std::uint32_t flags = 0;      ///< hidflags bits
  std::int32_t logicalMin = 0;
  std::int32_t logicalMax = 0;
  std::int32_t physicalMin = 0;  ///< equal to the logical range when the descriptor gives none
  std::int32_t physicalMax = 0;
  std::uint32_t unit = 0;         ///< HID unit code (system nibble + exponents of each dimension)
  std::int32_t unitExponent = 0;  ///< value × 10^unitExponent in `unit`
  /// Variable field: the usage of each element (count entries). Array field: the usage that an
  /// element value v selects is usages[v - logicalMin].
  std::vector<Usage> usages;
  Usage application = 0;  ///< usage of the enclosing Application collection

  bool isVariable() const noexcept { return (flags & hidflags::kVariable) != 0; }
  bool isConstant() const noexcept { return (flags & hidflags::kConstant) != 0; }
  bool isSigned() const noexcept { return logicalMin < 0; }
  bool hasNullState() const noexcept { return (flags & hidflags::kNullState) != 0; }
};

/// The size of one report.
struct HidReportInfo {
  HidReportType type = HidReportType::Input;
  std::uint8_t id = 0;
  std::uint32_t bitLength = 0;  ///< data bits, without the report ID byte

  /// Bytes on the wire: data rounded up, plus the ID byte when the descriptor numbers reports.
  std::size_t wireBytes(bool withId) const noexcept { return (bitLength + 7) / 8 + (withId ? 1 : 0); }
};

/// One collection, in descriptor order.
struct HidCollection {
  std::uint8_t type = 0;  ///< 0 physical, 1 application, 2 logical, 3 report, ...
  Usage usage = 0;
  int parent = -1;  ///< index in `collections`, -1 at top level
};

/// A parsed report descriptor.
struct HidReportDescriptor {
  std::vector<HidField> fields;        ///< data fields (padding is not listed; it only moves offsets)
  std::vector<HidReportInfo> reports;  ///< every report declared, in order of first appearance
  std::vector<HidCollection> collections;
  bool usesReportIds = false;

  /// The report of `type` with `id`, or nullptr.
  const HidReportInfo* report(HidReportType type, std::uint8_t id) const noexcept;
  /// Largest Input report in bytes on the wire (ID byte included).
  std::size_t maxInputReportBytes() const noexcept;
};

/// A descriptor that cannot be read. what() names the byte offset, the item and the reason.
class HidDescriptorError : public std::runtime_error {
 public:
  HidDescriptorError(std::size_t offset, const std::string& reason);
  /// Byte offset of the offending item in the descriptor.
  std::size_t offset() const noexcept { return mOffset; }

 private:
  std::size_t mOffset;
};

/// Limits that keep a hostile descriptor from asking for unbounded memory (Linux's values).
namespace hidlimits {
constexpr std::uint32_t kMaxReportSizeBits = 256;  ///< one element
constexpr std::uint32_t kMaxReportCount = 12288;   ///< elements per main item (HID_MAX_USAGES)
constexpr std::uint32_t kMaxUsagesPerItem = 12288;
/// Usages of all fields together. Linux bounds each field only, so a 2 KB descriptor of one-bit
/// array items can name millions; no real device comes near this, and it keeps field indices in
/// 16 bits.
constexpr std::uint32_t kMaxUsagesPerDescriptor = 16384;
constexpr std::uint32_t kMaxReportBytes = 16384;  ///< one report, ID included (HID_MAX_BUFFER_SIZE)
constexpr std::uint32_t kMaxGlobalStack = 16;     ///< Push depth
constexpr std::uint32_t kMaxCollectionDepth = 64;
}  // namespace hidlimits

/// Parses a report descriptor. Throws HidDescriptorError on malformed input. Not RT-safe.
HidReportDescriptor parseHidReportDescriptor(std::span<const std::uint8_t> bytes);

/// Reads a report descriptor from a file: raw bytes (e.g. /sys/class/hidraw/hidraw0/device/report_descriptor),
/// hex text ("05 01 09 04 …", "0x05, 0x01, …", `xxd -p` runs, with #, // or /* */ comments), a
/// usbhid-dump capture, or a hid-recorder file's "R: <length> <hex…>" line. Throws
/// std::runtime_error naming the file (and the line, for text). Not RT-safe.
std::vector<std::uint8_t> readHidDescriptorFile(const std::string& path);

/// Readable unit ("deg", "cm", "s", "none", or the raw code) of a field. Not RT-safe.
std::string describeHidUnit(std::uint32_t unit, std::int32_t exponent);

}  // namespace fieldcast::io
