// libusb's hotplug callback as a DeviceArrivalWatch for StickInput's reconnect wait.
#include <io_bridge/UsbHotplug.h>

#include <libusb.h>

#include <stdexcept>

namespace fieldcast::io {
namespace {

class LibusbHotplugBus final : public UsbHotplugBus {
 public:
  LibusbHotplugBus() {
    const int rc = libusb_init(&mContext);
    if (rc != 0) throw std::runtime_error(std::string("libusb_init: ") + libusb_error_name(rc));
  }
  ~LibusbHotplugBus() override {
    if (mRegistered) libusb_hotplug_deregister_callback(mContext, mHandle);
    libusb_exit(mContext);
  }
  LibusbHotplugBus(const LibusbHotplugBus&) = delete;
  LibusbHotplugBus& operator=(const LibusbHotplugBus&) = delete;

  bool hasHotplug() const override { return libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG) != 0; }

  void watchArrivals(std::optional<std::uint16_t> vendorId, std::optional<std::uint16_t> productId,
                     std::function<void()> onArrival) override {
    mOnArrival = std::move(onArrival);
    const int rc = libusb_hotplug_register_callback(
        mContext, LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED, LIBUSB_HOTPLUG_NO_FLAGS,
        vendorId ? *vendorId : LIBUSB_HOTPLUG_MATCH_ANY, productId ? *productId : LIBUSB_HOTPLUG_MATCH_ANY,
        LIBUSB_HOTPLUG_MATCH_ANY, &LibusbHotplugBus::arrived, this, &mHandle);
    if (rc != LIBUSB_SUCCESS) {
      throw std::runtime_error(std::string("libusb_hotplug_register_callback: ") + libusb_error_name(rc));
    }
    mRegistered = true;
  }

  void handleEvents(Nanoseconds timeout) override {
    const auto us = std::chrono::duration_cast<std::chrono::microseconds>(timeout).count();
    timeval tv{static_cast<time_t>(us / 1000000), static_cast<suseconds_t>(us % 1000000)};
    libusb_handle_events_timeout_completed(mContext, &tv, nullptr);
  }

 private:
  // libusb calls this from handleEvents(): no libusb calls here, only the flag.
  static int LIBUSB_CALL arrived(libusb_context*, libusb_device*, libusb_hotplug_event, void* self) {
    static_cast<LibusbHotplugBus*>(self)->mOnArrival();
    return 0;  // stay registered
  }

  libusb_context* mContext = nullptr;
  libusb_hotplug_callback_handle mHandle{};
  bool mRegistered = false;
  std::function<void()> mOnArrival;
};

class UsbArrivalWatch final : public DeviceArrivalWatch {
 public:
  UsbArrivalWatch(std::unique_ptr<UsbHotplugBus> bus, const UsbDeviceSelector& selector) : mBus(std::move(bus)) {
    mBus->watchArrivals(selector.vendorId, selector.productId, [this] { mArrived = true; });
  }
  bool waitForArrival(Nanoseconds timeout) override {
    if (!mArrived) mBus->handleEvents(timeout);
    const bool arrived = mArrived;
    mArrived = false;
    return arrived;
  }

 private:
  std::unique_ptr<UsbHotplugBus> mBus;
  bool mArrived = false;  // set by the callback, which runs inside handleEvents() on this thread
};

}  // namespace

std::unique_ptr<UsbHotplugBus> openLibusbHotplugBus() { return std::make_unique<LibusbHotplugBus>(); }

std::unique_ptr<DeviceArrivalWatch> watchUsbArrivals(std::unique_ptr<UsbHotplugBus> bus,
                                                     const UsbDeviceSelector& selector) {
  if (!bus || !bus->hasHotplug()) return nullptr;
  return std::make_unique<UsbArrivalWatch>(std::move(bus), selector);
}

}  // namespace fieldcast::io
