// The libusb side of UsbHidSource: device selection, kernel-driver detach, GET_DESCRIPTOR(Report)
// (HID 1.11 §7.1.1) and asynchronous interrupt-IN transfers that resubmit themselves.
#include <io_bridge/UsbHidSource.h>

#include <libusb.h>

#include <array>
#include <cstdio>
#include <deque>
#include <stdexcept>

namespace fieldcast::io {
namespace {

std::string usbError(int rc) { return libusb_error_name(rc); }

std::string hex4(std::uint16_t v) {
  std::array<char, 8> b{};
  std::snprintf(b.data(), b.size(), "%04x", v);
  return b.data();
}

struct Context {
  libusb_context* ctx = nullptr;
  Context() {
    const int rc = libusb_init(&ctx);
    if (rc != 0) throw std::runtime_error("libusb_init: " + usbError(rc));
  }
  ~Context() {
    if (ctx != nullptr) libusb_exit(ctx);
  }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
};

// The interface of `cls` with an interrupt-IN endpoint: number, endpoint, packet size, HID
// descriptor's report-descriptor length (0 when the interface has no HID descriptor).
struct Match {
  int interfaceNumber = -1;
  std::uint8_t endpoint = 0;
  int packetSize = 0;
  int reportDescriptorLength = 0;
};

Match findInterface(libusb_device* dev, std::uint8_t cls, int wantedNumber) {
  Match m;
  libusb_config_descriptor* config = nullptr;
  if (libusb_get_active_config_descriptor(dev, &config) != 0 && libusb_get_config_descriptor(dev, 0, &config) != 0) {
    return m;
  }
  for (int i = 0; i < config->bNumInterfaces && m.interfaceNumber < 0; ++i) {
    const libusb_interface& itf = config->interface[i];
    if (itf.num_altsetting < 1) continue;
    const libusb_interface_descriptor& alt = itf.altsetting[0];
    if (alt.bInterfaceClass != cls) continue;
    if (wantedNumber >= 0 && alt.bInterfaceNumber != wantedNumber) continue;
    for (int e = 0; e < alt.bNumEndpoints; ++e) {
      const libusb_endpoint_descriptor& ep = alt.endpoint[e];
      if ((ep.bmAttributes & 0x3) == LIBUSB_TRANSFER_TYPE_INTERRUPT && (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN)) {
        m.interfaceNumber = alt.bInterfaceNumber;
        m.endpoint = ep.bEndpointAddress;
        m.packetSize = ep.wMaxPacketSize;
        break;
      }
    }
    // The class descriptor (type 0x21) follows the interface descriptor: … bNumDescriptors, then
    // (bDescriptorType, wDescriptorLength) pairs; type 0x22 is the report descriptor.
    for (int off = 0; m.interfaceNumber >= 0 && off + 1 < alt.extra_length;) {
      const unsigned char* d = alt.extra + off;
      const int len = d[0];
      if (len < 2 || off + len > alt.extra_length) break;
      if (d[1] == 0x21 && len >= 9) {
        for (int k = 0; k < d[5] && 6 + 3 * k + 2 < len; ++k) {
          if (d[6 + 3 * k] == 0x22) m.reportDescriptorLength = d[7 + 3 * k] | (d[8 + 3 * k] << 8);
        }
      }
      off += len;
    }
  }
  libusb_free_config_descriptor(config);
  return m;
}

std::string productString(libusb_device_handle* h, const libusb_device_descriptor& dd) {
  std::array<unsigned char, 128> s{};
  if (h != nullptr && dd.iProduct != 0 &&
      libusb_get_string_descriptor_ascii(h, dd.iProduct, s.data(), static_cast<int>(s.size())) > 0) {
    return reinterpret_cast<const char*>(s.data());
  }
  return "USB " + hex4(dd.idVendor) + ":" + hex4(dd.idProduct);
}

// bmRequestType of a standard request to an interface, device to host.
constexpr std::uint8_t kStandardInterfaceIn =
    0x81;  // LIBUSB_ENDPOINT_IN | LIBUSB_REQUEST_TYPE_STANDARD | LIBUSB_RECIPIENT_INTERFACE

class LibusbTransport final : public UsbTransport {
 public:
  explicit LibusbTransport(const UsbDeviceSelector& sel) : mSelector(sel) {
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(mContext.ctx, &list);
    if (n < 0) throw std::runtime_error("libusb_get_device_list: " + usbError(static_cast<int>(n)));
    libusb_device* chosen = nullptr;
    for (ssize_t i = 0; i < n && chosen == nullptr; ++i) {
      libusb_device_descriptor dd{};
      if (libusb_get_device_descriptor(list[i], &dd) != 0) continue;
      if (sel.vendorId && dd.idVendor != *sel.vendorId) continue;
      if (sel.productId && dd.idProduct != *sel.productId) continue;
      const Match m = findInterface(list[i], sel.interfaceClass, sel.interfaceNumber);
      if (m.interfaceNumber < 0) continue;
      chosen = list[i];
      mMatch = m;
      mDeviceDescriptor = dd;
    }
    if (chosen == nullptr) {
      libusb_free_device_list(list, 1);
      const std::string who = sel.vendorId ? hex4(*sel.vendorId) + ":" + (sel.productId ? hex4(*sel.productId) : "*")
                                           : std::string("(any)");
      throw std::runtime_error("no USB device " + who + " with an interrupt-IN interface of class " +
                               std::to_string(sel.interfaceClass));
    }
    const int rc = libusb_open(chosen, &mHandle);
    libusb_free_device_list(list, 1);
    if (rc != 0) throw std::runtime_error("libusb_open: " + usbError(rc) + " (check the udev rule / plugdev group)");
    mName = productString(mHandle, mDeviceDescriptor);
    if (sel.detachKernelDriver) {
      const int ad = libusb_set_auto_detach_kernel_driver(mHandle, 1);  // re-attached on release
      if (ad != 0 && ad != LIBUSB_ERROR_NOT_SUPPORTED) {
        close();
        throw std::runtime_error(mName + ": detach kernel driver: " + usbError(ad));
      }
    }
    const int claim = libusb_claim_interface(mHandle, mMatch.interfaceNumber);
    if (claim != 0) {
      close();
      throw std::runtime_error(
          mName + ": claim interface " + std::to_string(mMatch.interfaceNumber) + ": " + usbError(claim) +
          (claim == LIBUSB_ERROR_BUSY ? " (the kernel's usbhid holds it: set detach_kernel_driver)" : ""));
    }
    mClaimed = true;
  }

  ~LibusbTransport() override { close(); }

  std::string productName() const override { return mName; }
  std::uint16_t vendorId() const override { return mDeviceDescriptor.idVendor; }
  std::uint16_t productId() const override { return mDeviceDescriptor.idProduct; }

  std::vector<std::uint8_t> reportDescriptor() override {
    if (mMatch.reportDescriptorLength <= 0) {
      throw std::runtime_error(mName + ": interface " + std::to_string(mMatch.interfaceNumber) +
                               " has no HID descriptor; give the report descriptor in the configuration");
    }
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(mMatch.reportDescriptorLength));
    const int n = libusb_control_transfer(
        mHandle, kStandardInterfaceIn, LIBUSB_REQUEST_GET_DESCRIPTOR, static_cast<std::uint16_t>(LIBUSB_DT_REPORT << 8),
        static_cast<std::uint16_t>(mMatch.interfaceNumber), buf.data(), static_cast<std::uint16_t>(buf.size()), 1000);
    if (n < 0) throw std::runtime_error(mName + ": GET_DESCRIPTOR(Report): " + usbError(n));
    buf.resize(static_cast<std::size_t>(n));
    return buf;
  }

  void startReading() override {
    for (Transfer& t : mTransfers) {
      t.owner = this;
      t.buffer.resize(static_cast<std::size_t>(std::max(mMatch.packetSize, 8)));
      t.transfer = libusb_alloc_transfer(0);
      if (t.transfer == nullptr) throw std::runtime_error(mName + ": libusb_alloc_transfer failed");
      libusb_fill_interrupt_transfer(t.transfer, mHandle, mMatch.endpoint, t.buffer.data(),
                                     static_cast<int>(t.buffer.size()), &LibusbTransport::completed, &t, 0);
      const int rc = libusb_submit_transfer(t.transfer);
      if (rc != 0) throw std::runtime_error(mName + ": submit interrupt-IN transfer: " + usbError(rc));
      t.inFlight = true;
    }
  }

  bool poll(Nanoseconds timeout, const UsbReportCallback& onReport) override {
    timeval tv{static_cast<time_t>(timeout.count() / 1'000'000'000),
               static_cast<suseconds_t>((timeout.count() % 1'000'000'000) / 1000)};
    const int rc = libusb_handle_events_timeout_completed(mContext.ctx, &tv, nullptr);
    if (rc != 0 && rc != LIBUSB_ERROR_INTERRUPTED) mGone = true;
    while (!mReady.empty()) {
      onReport(mReady.front().bytes, mReady.front().completed);
      mReady.pop_front();
    }
    return !mGone;
  }

 private:
  struct Transfer {
    LibusbTransport* owner = nullptr;
    libusb_transfer* transfer = nullptr;
    std::vector<std::uint8_t> buffer;
    bool inFlight = false;
  };
  struct Report {
    std::vector<std::uint8_t> bytes;
    TimePoint completed;
  };

  // Runs inside libusb_handle_events (on the input thread).
  static void LIBUSB_CALL completed(libusb_transfer* transfer) {
    auto* t = static_cast<Transfer*>(transfer->user_data);
    LibusbTransport* self = t->owner;
    t->inFlight = false;
    switch (transfer->status) {
      case LIBUSB_TRANSFER_COMPLETED:
        self->mErrors = 0;  // errors in a row, not over the device's life
        self->mReady.push_back(
            Report{std::vector<std::uint8_t>(transfer->buffer, transfer->buffer + transfer->actual_length),
                   MonotonicClock::now()});
        break;
      case LIBUSB_TRANSFER_NO_DEVICE: self->mGone = true; return;
      case LIBUSB_TRANSFER_CANCELLED: return;
      default:  // error, stall, overflow: count and go on; a gone device shows as NO_DEVICE
        if (++self->mErrors > 100) self->mGone = true;
        break;
    }
    if (self->mClosing || self->mGone) return;
    // An unplug often ends the transfers with an error first, and the resubmission then fails
    // (LIBUSB_ERROR_NO_DEVICE): with no transfer left in flight no NO_DEVICE would ever come
    if (libusb_submit_transfer(transfer) == 0) {
      t->inFlight = true;
    } else {
      self->mGone = true;
    }
  }

  void close() noexcept {
    mClosing = true;
    for (Transfer& t : mTransfers) {
      if (t.inFlight) libusb_cancel_transfer(t.transfer);
    }
    for (int i = 0; i < 100; ++i) {  // let the cancellations complete before freeing
      bool any = false;
      for (const Transfer& t : mTransfers) any = any || t.inFlight;
      if (!any) break;
      timeval tv{0, 10'000};
      libusb_handle_events_timeout_completed(mContext.ctx, &tv, nullptr);
    }
    for (Transfer& t : mTransfers) {
      if (t.transfer != nullptr && !t.inFlight) libusb_free_transfer(t.transfer);
      t.transfer = nullptr;
    }
    if (mHandle != nullptr) {
      if (mClaimed) libusb_release_interface(mHandle, mMatch.interfaceNumber);
      libusb_close(mHandle);
    }
    mHandle = nullptr;
    mClaimed = false;
  }

  UsbDeviceSelector mSelector;
  Context mContext;
  libusb_device_handle* mHandle = nullptr;
  libusb_device_descriptor mDeviceDescriptor{};
  Match mMatch;
  std::string mName;
  bool mClaimed = false;
  bool mClosing = false;
  bool mGone = false;
  int mErrors = 0;
  std::array<Transfer, 2> mTransfers;  // two in flight: no report lost while one is being handled
  std::deque<Report> mReady;
};

}  // namespace

std::vector<UsbDeviceInfo> listUsbDevices(std::uint8_t interfaceClass) {
  Context context;
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(context.ctx, &list);
  if (n < 0) throw std::runtime_error("libusb_get_device_list: " + usbError(static_cast<int>(n)));
  std::vector<UsbDeviceInfo> out;
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor dd{};
    if (libusb_get_device_descriptor(list[i], &dd) != 0) continue;
    const Match m = findInterface(list[i], interfaceClass, -1);
    if (m.interfaceNumber < 0) continue;
    libusb_device_handle* h = nullptr;
    const bool opened = libusb_open(list[i], &h) == 0;
    out.push_back({dd.idVendor, dd.idProduct, libusb_get_bus_number(list[i]), libusb_get_device_address(list[i]),
                   m.interfaceNumber, productString(opened ? h : nullptr, dd)});
    if (opened) libusb_close(h);
  }
  libusb_free_device_list(list, 1);
  return out;
}

std::unique_ptr<UsbTransport> openLibusbTransport(const UsbDeviceSelector& selector) {
  return std::make_unique<LibusbTransport>(selector);
}

}  // namespace fieldcast::io
