#pragma once
// Turns raw HID input reports into values, using a parsed report descriptor. Everything is laid
// out at construction; decode() allocates nothing and never throws, so it runs on the input
// thread at the device's report rate. HidInputTranslator then turns values into InputEvents,
// emitting only what changed.

#include <io_bridge/HidReportDescriptor.h>
#include <io_bridge/InputEvent.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace fieldcast::io {

/// Why a report was (not) decoded.
enum class HidDecodeStatus : std::uint8_t {
  Ok,
  Empty,          ///< zero bytes
  UnknownReport,  ///< report ID not declared as an Input report
  ShortReport,    ///< fewer bytes than the descriptor declares for that report
};

/// One decoded element. For array fields, one entry per selected usage (value 1).
struct HidValue {
  Usage usage = 0;
  std::int32_t value = 0;
  std::uint16_t fieldIndex = 0;  ///< index into HidReportDescriptor::fields
  bool isNull = false;           ///< out of the logical range on a field with a null state
  bool fromArray = false;
};

/// The outcome of decoding one report. `values` stays valid until the next decode().
struct HidDecodeResult {
  HidDecodeStatus status = HidDecodeStatus::Ok;
  std::uint8_t reportId = 0;
  std::uint32_t gotBytes = 0;   ///< bytes received
  std::uint32_t needBytes = 0;  ///< bytes the descriptor declares (ID byte included)
  std::span<const HidValue> values;
};

/// One sentence explaining a failed decode ("report 1: 12 bytes, the descriptor declares 64"). Not RT-safe.
std::string describe(const HidDecodeResult& result);

/// Decodes Input reports of one descriptor. One thread at a time.
class HidReportDecoder {
 public:
  explicit HidReportDecoder(HidReportDescriptor descriptor);

  /// Decodes one report as read from hidraw or the interrupt endpoint (ID byte first when the
  /// descriptor numbers its reports). Longer reports are accepted (devices pad). RT-safe.
  HidDecodeResult decode(std::span<const std::uint8_t> report) noexcept;

  const HidReportDescriptor& descriptor() const noexcept { return mDescriptor; }

  /// Extracts `bitSize` (1..32) bits at `bitOffset` little-endian, sign-extended when `isSigned`.
  /// The scalar reference every decode uses. RT-safe.
  static std::int32_t extract(std::span<const std::uint8_t> data, std::uint32_t bitOffset, std::uint32_t bitSize,
                              bool isSigned) noexcept;

 private:
  struct ReportPlan {
    std::uint8_t id = 0;
    std::uint32_t needBytes = 0;
    std::vector<std::uint16_t> fields;  // indices of the Input fields of this report
  };
  HidReportDescriptor mDescriptor;
  std::vector<ReportPlan> mPlans;
  std::vector<HidValue> mValues;  // sized for the largest report
};

/// Turns decoded reports into InputEvents: axes and buttons by usage, hat switches normalised to
/// 0..7 (clockwise from up) or kHatCentred, array selections into button presses and releases.
/// Only values that changed since the previous report are emitted. One thread at a time.
class HidInputTranslator {
 public:
  explicit HidInputTranslator(HidReportDescriptor descriptor);

  /// The controls this device reports (for DeviceDescription::controls).
  const std::vector<ControlInfo>& controls() const noexcept { return mControls; }

  /// Decodes `report` and appends its changes plus a Sync at `tNs` to `out` (no Sync when nothing
  /// changed). Returns the decode result so the caller can count and log rejects. Allocates only
  /// if `out` must grow.
  HidDecodeResult translate(std::span<const std::uint8_t> report, std::int64_t tNs, std::vector<InputEvent>& out);

 private:
  std::int32_t normalise(const HidValue& v) const noexcept;
  int controlIndex(Usage usage) const noexcept;

  HidReportDecoder mDecoder;
  std::vector<ControlInfo> mControls;
  // Usage → control index: open addressing in a power-of-two table at most half full (usage 0,
  // never a control, marks a free slot). Built once with no allocation per usage, since a
  // descriptor may declare thousands; lookups on the input thread never allocate.
  class UsageIndex {
   public:
    void reserve(std::size_t usages);  ///< room for this many distinct usages; empties the index
    /// The index stored for `usage`, or `index` stored for it when it has none yet.
    std::pair<int, bool> insert(Usage usage, int index);
    int find(Usage usage) const noexcept;  ///< −1 when absent

   private:
    std::size_t home(Usage usage) const noexcept;
    std::vector<std::pair<Usage, int>> mSlots;
    int mShift = 32;
  };
  UsageIndex mIndex;
  std::vector<std::int32_t> mLast;  // last emitted value per control
  std::vector<bool> mSeen;          // control reported at least once
  std::vector<std::uint8_t> mTouched;
  std::array<std::vector<int>, 256> mArrayControls;  // per report ID: controls selected through arrays
};

}  // namespace fieldcast::io
