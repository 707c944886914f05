#include <io_bridge/UsbHidSource.h>

#include <charconv>
#include <stdexcept>

namespace fieldcast::io {

UsbDeviceSelector parseUsbSelector(const std::string& text) {
  UsbDeviceSelector s;
  const auto colon = text.find(':');
  auto hex16 = [&](std::string_view part) {
    std::uint32_t v = 0;
    const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), v, 16);
    if (part.empty() || ec != std::errc{} || end != part.data() + part.size() || v > 0xFFFF) {
      throw std::runtime_error("USB device \"" + text + "\": expected vendor:product in hexadecimal, like 044f:0409");
    }
    return static_cast<std::uint16_t>(v);
  };
  if (colon == std::string::npos) {
    throw std::runtime_error("USB device \"" + text + "\": expected vendor:product in hexadecimal, like 044f:0409");
  }
  const std::string_view all(text);
  s.vendorId = hex16(all.substr(0, colon));
  s.productId = hex16(all.substr(colon + 1));
  return s;
}

UsbHidSource::UsbHidSource(std::unique_ptr<UsbTransport> transport, std::vector<std::uint8_t> descriptorOverride)
    : mTransport(std::move(transport)) {
  const std::vector<std::uint8_t> bytes =
      descriptorOverride.empty() ? mTransport->reportDescriptor() : std::move(descriptorOverride);
  HidReportDescriptor parsed;
  try {
    parsed = parseHidReportDescriptor(bytes);
  } catch (const HidDescriptorError& e) {
    throw std::runtime_error("USB " + mTransport->productName() + ": " + e.what());
  }
  mTranslator = std::make_unique<HidInputTranslator>(std::move(parsed));
  mDescription.name = mTransport->productName();
  mDescription.transport = InputTransport::Usb;
  mDescription.vendorId = mTransport->vendorId();
  mDescription.productId = mTransport->productId();
  mDescription.controls = mTranslator->controls();
  if (mDescription.controls.empty()) throw std::runtime_error("USB " + mDescription.name + ": no input controls");
  mOnReport = [this](std::span<const std::uint8_t> report, TimePoint completed) {
    const HidDecodeResult r = mTranslator->translate(report, completed.time_since_epoch().count(), *mOut);
    if (r.status == HidDecodeStatus::Ok) {
      ++mStats.frames;
    } else {
      ++mStats.rejectedReports;
    }
  };
  mTransport->startReading();
}

ReadResult UsbHidSource::read(std::vector<InputEvent>& out, Nanoseconds timeout) {
  const std::size_t before = out.size();
  mOut = &out;
  const bool alive = mTransport->poll(timeout, mOnReport);
  mOut = nullptr;
  if (out.size() != before) return ReadResult::Events;  // deliver what came; a loss shows on the next read
  return alive ? ReadResult::Timeout : ReadResult::Lost;
}

}  // namespace fieldcast::io
