#include <io_bridge/HidrawSource.h>

#include "input/SystemError.h"

#include <fcntl.h>
#include <linux/hidraw.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace fieldcast::io {

namespace {

std::string rawName(int fd) {
  std::array<char, 256> name{};
  if (::ioctl(fd, HIDIOCGRAWNAME(name.size() - 1), name.data()) < 0) return {};
  return name.data();
}

}  // namespace

std::vector<HidrawDeviceInfo> listHidrawDevices() {
  std::vector<HidrawDeviceInfo> out;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/dev", ec)) {
    const std::string file = entry.path().filename().string();
    if (file.rfind("hidraw", 0) != 0) continue;
    const int fd = ::open(entry.path().c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) continue;
    hidraw_devinfo info{};
    if (::ioctl(fd, HIDIOCGRAWINFO, &info) == 0) {
      out.push_back({entry.path().string(), rawName(fd), info.bustype, static_cast<std::uint16_t>(info.vendor),
                     static_cast<std::uint16_t>(info.product)});
    }
    ::close(fd);
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.path < b.path; });
  return out;
}

HidrawSource::HidrawSource(const std::string& path) : mPath(path) {
  mFd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (mFd < 0) throw std::runtime_error("hidraw " + path + ": " + errnoMessage(errno));
  try {
    int size = 0;
    if (::ioctl(mFd, HIDIOCGRDESCSIZE, &size) < 0) {
      throw std::runtime_error("hidraw " + path + ": not a hidraw device (HIDIOCGRDESCSIZE: " + errnoMessage(errno) +
                               ")");
    }
    hidraw_report_descriptor desc{};
    desc.size = static_cast<std::uint32_t>(std::clamp(size, 0, HID_MAX_DESCRIPTOR_SIZE));
    if (::ioctl(mFd, HIDIOCGRDESC, &desc) < 0) {
      throw std::runtime_error("hidraw " + path + ": HIDIOCGRDESC: " + errnoMessage(errno));
    }
    setUp(std::span<const std::uint8_t>(desc.value, desc.size));
    hidraw_devinfo info{};
    if (::ioctl(mFd, HIDIOCGRAWINFO, &info) == 0) {
      mDescription.vendorId = static_cast<std::uint16_t>(info.vendor);
      mDescription.productId = static_cast<std::uint16_t>(info.product);
    }
    mDescription.name = rawName(mFd);
    if (mDescription.name.empty()) mDescription.name = path;
  } catch (...) {
    ::close(mFd);
    throw;
  }
}

HidrawSource::HidrawSource(int fd, std::span<const std::uint8_t> descriptor, std::string name) : mFd(fd), mPath(name) {
  try {
    setUp(descriptor);
  } catch (...) {
    ::close(mFd);
    throw;
  }
  mDescription.name = std::move(name);
}

void HidrawSource::setUp(std::span<const std::uint8_t> descriptor) {
  mDescriptorBytes.assign(descriptor.begin(), descriptor.end());
  HidReportDescriptor parsed;
  try {
    parsed = parseHidReportDescriptor(mDescriptorBytes);
  } catch (const HidDescriptorError& e) {
    throw std::runtime_error("hidraw " + mPath + ": " + e.what());
  }
  mBuffer.resize(std::max<std::size_t>(parsed.maxInputReportBytes(), 64) + 64);
  mTranslator = std::make_unique<HidInputTranslator>(std::move(parsed));
  mDescription.transport = InputTransport::Hidraw;
  mDescription.controls = mTranslator->controls();
  if (mDescription.controls.empty()) {
    throw std::runtime_error("hidraw " + mPath + ": the descriptor declares no input controls");
  }
}

HidrawSource::~HidrawSource() {
  if (mFd >= 0) ::close(mFd);
}

ReadResult HidrawSource::read(std::vector<InputEvent>& out, Nanoseconds timeout) {
  pollfd p{mFd, POLLIN, 0};
  const auto ms = static_cast<int>(std::max<std::int64_t>(0, (timeout.count() + 999'999) / 1'000'000));
  const int ready = ::poll(&p, 1, ms);
  if (ready < 0) return errno == EINTR ? ReadResult::Timeout : ReadResult::Lost;
  if (ready == 0) return ReadResult::Timeout;
  const std::size_t before = out.size();
  // Each read() returns exactly one report; drain what is queued.
  for (int i = 0; i < 64; ++i) {
    const ssize_t n = ::read(mFd, mBuffer.data(), mBuffer.size());
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) break;
    if (n < 0) return ReadResult::Lost;  // ENODEV: unplugged
    if (n == 0) return ReadResult::Lost;
    const std::int64_t tNs = MonotonicClock::now().time_since_epoch().count();
    const HidDecodeResult r =
        mTranslator->translate(std::span<const std::uint8_t>(mBuffer.data(), static_cast<std::size_t>(n)), tNs, out);
    if (r.status == HidDecodeStatus::Ok) {
      ++mStats.frames;
    } else {
      ++mStats.rejectedReports;
    }
  }
  return out.size() != before ? ReadResult::Events : ReadResult::Timeout;
}

}  // namespace fieldcast::io
