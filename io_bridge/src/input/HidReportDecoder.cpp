// HID input-report decoding: bit extraction per HID 1.11 §5.8 (little-endian, fields packed from
// bit 0 of the first data byte), then per-usage change detection for the event stream.
#include <io_bridge/HidReportDecoder.h>

#include <algorithm>
#include <bit>

namespace fieldcast::io {

std::string describe(const HidDecodeResult& r) {
  const std::string id = "report " + std::to_string(r.reportId);
  switch (r.status) {
    case HidDecodeStatus::Ok: return id + ": ok";
    case HidDecodeStatus::Empty: return "empty report (0 bytes)";
    case HidDecodeStatus::UnknownReport: return id + ": not an Input report of this descriptor";
    case HidDecodeStatus::ShortReport:
      return id + ": " + std::to_string(r.gotBytes) + " bytes, the descriptor declares " + std::to_string(r.needBytes);
  }
  return "unknown status";
}

std::int32_t HidReportDecoder::extract(std::span<const std::uint8_t> data, std::uint32_t bitOffset,
                                       std::uint32_t bitSize, bool isSigned) noexcept {
  bitSize = std::min<std::uint32_t>(bitSize, 32);  // wider elements: low 32 bits, as Linux does
  if (bitSize == 0) return 0;
  const std::size_t first = bitOffset / 8;
  const std::size_t last = (std::size_t{bitOffset} + bitSize - 1) / 8;
  std::uint64_t acc = 0;
  for (std::size_t i = first; i <= last && i < data.size(); ++i) acc |= std::uint64_t{data[i]} << (8 * (i - first));
  acc >>= bitOffset % 8;
  const std::uint64_t mask = bitSize == 32 ? 0xFFFFFFFFull : ((1ull << bitSize) - 1);
  std::uint64_t v = acc & mask;
  if (isSigned && bitSize < 32 && (v >> (bitSize - 1)) != 0) v |= ~mask;  // sign-extend
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(v & 0xFFFFFFFFull));
}

HidReportDecoder::HidReportDecoder(HidReportDescriptor descriptor) : mDescriptor(std::move(descriptor)) {
  std::size_t most = 0;
  for (const HidReportInfo& r : mDescriptor.reports) {
    if (r.type != HidReportType::Input) continue;
    ReportPlan plan;
    plan.id = r.id;
    plan.needBytes = static_cast<std::uint32_t>(r.wireBytes(mDescriptor.usesReportIds));
    std::size_t values = 0;
    for (std::size_t i = 0; i < mDescriptor.fields.size(); ++i) {
      const HidField& f = mDescriptor.fields[i];
      if (f.type != HidReportType::Input || f.reportId != r.id || f.isConstant()) continue;
      plan.fields.push_back(static_cast<std::uint16_t>(i));
      values += f.count;
    }
    most = std::max(most, values);
    mPlans.push_back(std::move(plan));
  }
  mValues.resize(most);
}

HidDecodeResult HidReportDecoder::decode(std::span<const std::uint8_t> report) noexcept {
  HidDecodeResult result;
  result.gotBytes = static_cast<std::uint32_t>(report.size());
  if (report.empty()) {
    result.status = HidDecodeStatus::Empty;
    return result;
  }
  const std::uint8_t id = mDescriptor.usesReportIds ? report[0] : 0;
  result.reportId = id;
  const ReportPlan* plan = nullptr;
  for (const ReportPlan& p : mPlans) {
    if (p.id == id) plan = &p;
  }
  if (plan == nullptr) {
    result.status = HidDecodeStatus::UnknownReport;
    return result;
  }
  result.needBytes = plan->needBytes;
  if (report.size() < plan->needBytes) {
    result.status = HidDecodeStatus::ShortReport;
    return result;
  }
  const std::span<const std::uint8_t> data = mDescriptor.usesReportIds ? report.subspan(1) : report;
  std::size_t n = 0;
  for (const std::uint16_t fi : plan->fields) {
    const HidField& f = mDescriptor.fields[fi];
    for (std::uint32_t e = 0; e < f.count; ++e) {
      const std::int32_t raw = extract(data, f.bitOffset + e * f.bitSize, f.bitSize, f.isSigned());
      const bool inRange = f.isSigned()
                               ? (raw >= f.logicalMin && raw <= f.logicalMax)
                               : (static_cast<std::uint32_t>(raw) >= static_cast<std::uint32_t>(f.logicalMin) &&
                                  static_cast<std::uint32_t>(raw) <= static_cast<std::uint32_t>(f.logicalMax));
      if (f.isVariable()) {
        mValues[n++] = HidValue{f.usages[e], raw, fi, !inRange && f.hasNullState(), false};
      } else {
        // Array: the element names the usage that is active; out of range means "none".
        if (!inRange) continue;
        const std::int64_t index = std::int64_t{raw} - f.logicalMin;
        if (index < 0 || static_cast<std::size_t>(index) >= f.usages.size()) continue;
        const Usage u = f.usages[static_cast<std::size_t>(index)];
        if (u == 0) continue;  // usage 0 in an array is "no event"
        mValues[n++] = HidValue{u, 1, fi, false, true};
      }
    }
  }
  result.values = std::span<const HidValue>(mValues.data(), n);
  return result;
}

HidInputTranslator::HidInputTranslator(HidReportDescriptor descriptor) : mDecoder(std::move(descriptor)) {
  const HidReportDescriptor& d = mDecoder.descriptor();
  std::size_t usages = 0;
  for (const HidField& f : d.fields) usages += f.usages.size();
  mIndex.reserve(usages);
  std::vector<int> listedInReport;  // per control: 1 + the report whose array list has it last
  for (const HidField& f : d.fields) {
    if (f.type != HidReportType::Input || f.isConstant()) continue;
    for (const Usage u : f.usages) {
      if (u == 0) continue;
      const auto [control, added] = mIndex.insert(u, static_cast<int>(mControls.size()));
      if (added) listedInReport.push_back(0);
      // Array selections of each report, for releasing what a report no longer selects.
      int& listed = listedInReport[static_cast<std::size_t>(control)];
      if (!f.isVariable() && listed != f.reportId + 1) {
        mArrayControls[f.reportId].push_back(control);
        listed = f.reportId + 1;
      }
      if (!added) continue;
      ControlInfo c;
      c.usage = u;
      c.kind = kindOfUsage(u);
      if (c.kind == ControlKind::Hat) {
        c.min = 0;
        c.max = kHatCentred;
      } else if (!f.isVariable()) {
        c.kind = ControlKind::Button;  // an array selection is a press
        c.min = 0;
        c.max = 1;
      } else {
        c.min = f.logicalMin;
        c.max = f.logicalMax;
      }
      mControls.push_back(c);
    }
  }
  for (std::vector<int>& list : mArrayControls) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  mLast.assign(mControls.size(), 0);
  mSeen.assign(mControls.size(), false);
  mTouched.assign(mControls.size(), 0);
}

int HidInputTranslator::controlIndex(Usage usage) const noexcept { return mIndex.find(usage); }

void HidInputTranslator::UsageIndex::reserve(std::size_t usages) {
  const std::size_t slots = std::bit_ceil(std::max<std::size_t>(2 * usages, 8));
  mShift = 32 - std::countr_zero(slots);
  mSlots.assign(slots, {0, -1});
}

std::size_t HidInputTranslator::UsageIndex::home(Usage usage) const noexcept {
  return (usage * 0x9E3779B1u) >> mShift;  // Fibonacci hashing: the top bits of the product
}

std::pair<int, bool> HidInputTranslator::UsageIndex::insert(Usage usage, int index) {
  for (std::size_t i = home(usage);; i = (i + 1) & (mSlots.size() - 1)) {
    if (mSlots[i].first == usage) return {mSlots[i].second, false};
    if (mSlots[i].first == 0) {
      mSlots[i] = {usage, index};
      return {index, true};
    }
  }
}

int HidInputTranslator::UsageIndex::find(Usage usage) const noexcept {
  if (mSlots.empty() || usage == 0) return -1;
  for (std::size_t i = home(usage);; i = (i + 1) & (mSlots.size() - 1)) {
    if (mSlots[i].first == usage) return mSlots[i].second;
    if (mSlots[i].first == 0) return -1;
  }
}

std::int32_t HidInputTranslator::normalise(const HidValue& v) const noexcept {
  if (kindOfUsage(v.usage) != ControlKind::Hat) return v.value;
  const HidField& f = mDecoder.descriptor().fields[v.fieldIndex];
  const std::int64_t span = std::int64_t{f.logicalMax} - f.logicalMin + 1;
  const std::int64_t rel = std::int64_t{v.value} - f.logicalMin;
  if (v.isNull || rel < 0 || rel >= span || span <= 0) return kHatCentred;
  return static_cast<std::int32_t>(rel * 8 / span);  // 4- and 8-position hats alike
}

HidDecodeResult HidInputTranslator::translate(std::span<const std::uint8_t> report, std::int64_t tNs,
                                              std::vector<InputEvent>& out) {
  const HidDecodeResult r = mDecoder.decode(report);
  if (r.status != HidDecodeStatus::Ok) return r;
  const std::size_t before = out.size();
  std::fill(mTouched.begin(), mTouched.end(), 0);
  for (const HidValue& v : r.values) {
    const int ci = controlIndex(v.usage);
    if (ci < 0) continue;
    const auto i = static_cast<std::size_t>(ci);
    if (mTouched[i]) continue;  // a usage repeated in one report: the first element counts
    if (v.isNull && kindOfUsage(v.usage) != ControlKind::Hat) continue;  // no reading: keep the last
    const std::int32_t value = normalise(v);
    mTouched[i] = 1;
    if (mSeen[i] && mLast[i] == value) continue;
    mSeen[i] = true;
    mLast[i] = value;
    out.push_back(InputEvent{tNs, v.usage, value, InputEventType::Value});
  }
  // Array selections of this report that it no longer selects are released.
  for (const int ci : mArrayControls[r.reportId]) {
    const auto i = static_cast<std::size_t>(ci);
    if (mTouched[i] || !mSeen[i] || mLast[i] == 0) continue;
    mLast[i] = 0;
    out.push_back(InputEvent{tNs, mControls[i].usage, 0, InputEventType::Value});
  }
  if (out.size() != before) out.push_back(InputEvent{tNs, 0, 0, InputEventType::Sync});
  return r;
}

}  // namespace fieldcast::io
