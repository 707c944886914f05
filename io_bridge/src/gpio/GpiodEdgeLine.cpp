// Both-edge event lines through libgpiod v1 (the API of Debian 12's libgpiod 1.6).
#include <io_bridge/GpioInput.h>

#include "input/SystemError.h"

#include <gpiod.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <stdexcept>

namespace fieldcast::io {
namespace {

class GpiodEdgeLine final : public GpioEdgeLine {
 public:
  explicit GpiodEdgeLine(const GpioLineConfig& c) : mName(c.chip + ":" + std::to_string(c.offset)) {
    mChip = gpiod_chip_open_lookup(c.chip.c_str());
    if (mChip == nullptr) throw std::runtime_error("GPIO chip \"" + c.chip + "\": " + errnoMessage(errno));
    mLine = gpiod_chip_get_line(mChip, c.offset);
    if (mLine == nullptr) {
      const std::string why = errnoMessage(errno);
      gpiod_chip_close(mChip);
      throw std::runtime_error("GPIO " + mName + ": no such line (" + why + ")");
    }
    int flags = c.activeLow ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
    switch (c.bias) {
      case GpioBias::AsIs: break;
      case GpioBias::Disable: flags |= GPIOD_LINE_REQUEST_FLAG_BIAS_DISABLE; break;
      case GpioBias::PullUp: flags |= GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP; break;
      case GpioBias::PullDown: flags |= GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_DOWN; break;
    }
    if (gpiod_line_request_both_edges_events_flags(mLine, c.consumer.c_str(), flags) != 0) {
      const std::string why = errnoMessage(errno);
      const char* holder = gpiod_line_consumer(mLine);
      gpiod_chip_close(mChip);
      throw std::runtime_error("GPIO " + mName + ": edge events refused (" + why + ")" +
                               (holder != nullptr ? std::string(", line held by \"") + holder + "\"" : ""));
    }
    mFd = gpiod_line_event_get_fd(mLine);
  }
  ~GpiodEdgeLine() override {
    gpiod_line_release(mLine);
    gpiod_chip_close(mChip);
  }
  GpiodEdgeLine(const GpiodEdgeLine&) = delete;
  GpiodEdgeLine& operator=(const GpiodEdgeLine&) = delete;

  std::string name() const override { return mName; }
  int eventFd() const override { return mFd; }

  bool readEdges(std::vector<GpioEdge>& out) override {
    std::array<gpiod_line_event, 16> events{};
    const int n = gpiod_line_event_read_multiple(mLine, events.data(), static_cast<unsigned>(events.size()));
    if (n < 0) return errno == EAGAIN || errno == EINTR;
    // Kernels before 5.7 stamp v1 line events on CLOCK_REALTIME: move such stamps to MONOTONIC.
    timespec mono{}, real{};
    clock_gettime(CLOCK_MONOTONIC, &mono);
    clock_gettime(CLOCK_REALTIME, &real);
    const std::int64_t monoNs = fromTimespec(mono).time_since_epoch().count();
    const std::int64_t realNs = fromTimespec(real).time_since_epoch().count();
    for (int i = 0; i < n; ++i) {
      std::int64_t t = fromTimespec(events[static_cast<std::size_t>(i)].ts).time_since_epoch().count();
      if (t > monoNs + 3'600'000'000'000) t -= realNs - monoNs;
      out.push_back(GpioEdge{TimePoint{Nanoseconds{t}},
                             events[static_cast<std::size_t>(i)].event_type == GPIOD_LINE_EVENT_RISING_EDGE
                                 ? GpioEdgeKind::Rising
                                 : GpioEdgeKind::Falling});
    }
    return true;
  }

  bool level() override { return gpiod_line_get_value(mLine) == 1; }

 private:
  std::string mName;
  gpiod_chip* mChip = nullptr;
  gpiod_line* mLine = nullptr;
  int mFd = -1;
};

}  // namespace

std::unique_ptr<GpioEdgeLine> openGpiodEdgeLine(const GpioLineConfig& config) {
  return std::make_unique<GpiodEdgeLine>(config);
}

std::vector<std::string> listGpioChips() {
  std::vector<std::string> chips;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/dev", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("gpiochip", 0) == 0) chips.push_back(name);
  }
  std::sort(chips.begin(), chips.end());
  return chips;
}

}  // namespace fieldcast::io
