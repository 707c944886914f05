#pragma once
// A USB HID device read directly with libusb (no kernel HID driver): for cockpit panels that are
// not bound to usbhid, or when the kernel driver is detached on purpose. The report descriptor is
// fetched with GET_DESCRIPTOR(Report) and parsed by our parser; the interrupt-IN endpoint is read
// with asynchronous transfers. The transport is a seam: LibusbTransport talks to hardware, tests
// use a fake that delivers real report bytes. Reconnection after unplug is StickInput's backoff,
// woken early by a libusb hotplug arrival where the platform has it (UsbHotplug.h).

#include <io_bridge/HidReportDecoder.h>
#include <io_bridge/InputSource.h>

#include <fieldcast/Time.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace fieldcast::io {

/// Which USB device and interface to open.
struct UsbDeviceSelector {
  std::optional<std::uint16_t> vendorId;   ///< empty: any vendor
  std::optional<std::uint16_t> productId;  ///< empty: any product
  std::uint8_t interfaceClass = 3;         ///< 3 = HID; a vendor class (0xFF) for panels without usbhid
  int interfaceNumber = -1;                ///< −1: the first interface of that class with an interrupt-IN endpoint
  bool detachKernelDriver = false;         ///< detach usbhid (re-attached on close)
  std::vector<std::uint8_t>
      reportDescriptor;  ///< use this descriptor instead of asking the device (vendor-class panels)
};

/// Parses "046d:c215" into a selector. Throws std::runtime_error naming the text.
UsbDeviceSelector parseUsbSelector(const std::string& vidPid);

/// Called for each completed interrupt-IN transfer: the report bytes and when it completed.
using UsbReportCallback = std::function<void(std::span<const std::uint8_t> report, TimePoint completed)>;

/// What a USB HID source needs from the bus.
class UsbTransport {
 public:
  virtual ~UsbTransport() = default;
  /// Device name and IDs (for DeviceDescription).
  virtual std::string productName() const = 0;
  virtual std::uint16_t vendorId() const = 0;
  virtual std::uint16_t productId() const = 0;
  /// The HID report descriptor. Throws with the reason.
  virtual std::vector<std::uint8_t> reportDescriptor() = 0;
  /// Starts the asynchronous interrupt-IN reads. Throws with the reason.
  virtual void startReading() = 0;
  /// Waits up to `timeout` for completed transfers and hands each report to `onReport`.
  /// Returns false once the device is gone (LIBUSB_TRANSFER_NO_DEVICE).
  virtual bool poll(Nanoseconds timeout, const UsbReportCallback& onReport) = 0;
};

/// One USB device with a HID-class (or selected-class) interface.
struct UsbDeviceInfo {
  std::uint16_t vendorId = 0;
  std::uint16_t productId = 0;
  std::uint8_t bus = 0;
  std::uint8_t address = 0;
  int interfaceNumber = -1;
  std::string product;
};

/// Lists devices with an interface of `interfaceClass` and an interrupt-IN endpoint. Throws when
/// libusb cannot start. Not RT-safe.
std::vector<UsbDeviceInfo> listUsbDevices(std::uint8_t interfaceClass = 3);

/// Opens the device through libusb: claim the interface (detaching usbhid when configured),
/// ready to fetch the descriptor and read. Throws std::runtime_error with the reason
/// ("no USB device 044f:0409 with an interface of class 3", "claim interface 0: LIBUSB_ERROR_BUSY …").
std::unique_ptr<UsbTransport> openLibusbTransport(const UsbDeviceSelector& selector);

/// A USB HID device as an input source, over any UsbTransport.
class UsbHidSource final : public InputSource {
 public:
  /// Fetches and parses the descriptor (or uses `descriptorOverride`), then starts reading.
  explicit UsbHidSource(std::unique_ptr<UsbTransport> transport, std::vector<std::uint8_t> descriptorOverride = {});
  UsbHidSource(const UsbHidSource&) = delete;
  UsbHidSource& operator=(const UsbHidSource&) = delete;

  const DeviceDescription& description() const noexcept override { return mDescription; }
  ReadResult read(std::vector<InputEvent>& out, Nanoseconds timeout) override;
  InputSourceStats stats() const noexcept override { return mStats; }

 private:
  std::unique_ptr<UsbTransport> mTransport;
  std::unique_ptr<HidInputTranslator> mTranslator;
  DeviceDescription mDescription;
  InputSourceStats mStats;
  std::vector<InputEvent>* mOut = nullptr;
  UsbReportCallback mOnReport;
};

}  // namespace fieldcast::io
