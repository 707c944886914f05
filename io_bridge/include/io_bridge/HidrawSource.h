#pragma once
// A HID device read through the kernel's hidraw interface (/dev/hidrawN): the report descriptor
// comes from HIDIOCGRDESC and is parsed by our parser; each read() returns one raw report.
// hidraw carries no timestamp, so a report is stamped with CLOCK_MONOTONIC when read.

#include <io_bridge/HidReportDecoder.h>
#include <io_bridge/InputSource.h>

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace fieldcast::io {

/// One hidraw node found on the system.
struct HidrawDeviceInfo {
  std::string path;
  std::string name;
  std::uint32_t bus = 0;
  std::uint16_t vendorId = 0;
  std::uint16_t productId = 0;
};

/// Lists /dev/hidraw* that can be opened. Not RT-safe.
std::vector<HidrawDeviceInfo> listHidrawDevices();

/// A hidraw device as an input source. Construction opens it and parses its descriptor; throws
/// std::runtime_error naming the path and the reason.
class HidrawSource final : public InputSource {
 public:
  explicit HidrawSource(const std::string& path);
  /// Reads reports from `fd` (taken over; closed on destruction) with the given descriptor: the
  /// seam tests use with a SOCK_SEQPACKET socket, which keeps one report per read() as hidraw does.
  HidrawSource(int fd, std::span<const std::uint8_t> descriptor, std::string name);
  ~HidrawSource() override;
  HidrawSource(const HidrawSource&) = delete;
  HidrawSource& operator=(const HidrawSource&) = delete;

  const DeviceDescription& description() const noexcept override { return mDescription; }
  ReadResult read(std::vector<InputEvent>& out, Nanoseconds timeout) override;
  InputSourceStats stats() const noexcept override { return mStats; }
  /// The raw report descriptor as the kernel gave it.
  const std::vector<std::uint8_t>& reportDescriptor() const noexcept { return mDescriptorBytes; }

 private:
  int mFd = -1;
  std::string mPath;
  std::vector<std::uint8_t> mDescriptorBytes;
  std::unique_ptr<HidInputTranslator> mTranslator;
  DeviceDescription mDescription;
  InputSourceStats mStats;
  std::vector<std::uint8_t> mBuffer;

  void setUp(std::span<const std::uint8_t> descriptor);  // parse, size the buffer, describe
};

}  // namespace fieldcast::io
