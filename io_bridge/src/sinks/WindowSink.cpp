// Live window through OpenCV highgui. Debian's highgui is built on Qt, which abort()s the process
// when it cannot reach a display, so the display is probed first with a plain socket connection
// to the X server (the X11 display naming of X(7): [host]:display[.screen]).

#include <io_bridge/WindowSink.h>

#include "PixelConvert.h"

#include <opencv2/highgui.hpp>
#include <opencv2/imgproc.hpp>

#include <netdb.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

namespace fieldcast::io {

namespace {

// True when something accepts connections at the X display `display` (":0", "host:1.0").
bool xServerAnswers(const std::string& display) {
  const auto colon = display.rfind(':');
  if (colon == std::string::npos) return false;
  const std::string host = display.substr(0, colon);
  const int number = std::atoi(display.c_str() + colon + 1);
  if (host.empty() || host == "unix") {
    const std::string path = "/tmp/.X11-unix/X" + std::to_string(number);
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return false;
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::snprintf(a.sun_path, sizeof a.sun_path, "%s", path.c_str());
    const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    ::close(fd);
    return ok;
  }
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(host.c_str(), std::to_string(6000 + number).c_str(), &hints, &found) != 0) return false;
  bool ok = false;
  for (addrinfo* a = found; a && !ok; a = a->ai_next) {
    const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) continue;
    ok = ::connect(fd, a->ai_addr, a->ai_addrlen) == 0;
    ::close(fd);
  }
  freeaddrinfo(found);
  return ok;
}

// Qt's highgui lives in the first thread that uses it and routes every later call there
// (blocking): a second thread would wait forever on one that no longer pumps events.
std::mutex gGuiThreadMutex;
std::optional<std::thread::id> gGuiThread;

void claimGuiThread() {
  std::lock_guard lock(gGuiThreadMutex);
  if (!gGuiThread) gGuiThread = std::this_thread::get_id();
  if (*gGuiThread != std::this_thread::get_id()) {
    throw std::runtime_error("sinks.window: the GUI already belongs to another thread; one window thread per process");
  }
}

void drawText(cv::Mat& image, const std::string& text, int line) {
  const cv::Point at(8, 18 + 18 * line);
  cv::putText(image, text, at + cv::Point(1, 1), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 2, cv::LINE_AA);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(80, 255, 80), 1, cv::LINE_AA);
}

}  // namespace

WindowKey decodeWindowKey(int code) noexcept {
  switch (code) {
    // Qt backend (Qt::Key_* values) and GTK backend (X keysyms)
    case 0x01000012:
    case 65361:
    case 'a':
    case 'A': return WindowKey::Left;
    case 0x01000014:
    case 65363:
    case 'd':
    case 'D': return WindowKey::Right;
    case 0x01000013:
    case 65362:
    case 'w':
    case 'W': return WindowKey::Up;
    case 0x01000015:
    case 65364:
    case 's':
    case 'S': return WindowKey::Down;
    case '+':
    case '=': return WindowKey::Faster;
    case '-':
    case '_': return WindowKey::Slower;
    case 'r':
    case 'R': return WindowKey::Reset;
    case ' ': return WindowKey::Snapshot;
    case 27:
    case 'q':
    case 'Q': return WindowKey::Quit;
    default: return WindowKey::Other;
  }
}

std::string WindowSink::displayProblem() {
  const char* platform = std::getenv("QT_QPA_PLATFORM");
  if (platform && std::string(platform) != "xcb") return {};  // offscreen, wayland…: Qt's choice
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display) return "DISPLAY is not set: there is no screen to open a window on";
  if (!xServerAnswers(display)) return std::string("cannot connect to X display ") + display;
  return {};
}

struct WindowSink::State {
  StreamFormat format;
  cv::Mat picture;  // BGR, full raster, woven
  std::string title;
};

WindowSink::WindowSink(WindowSinkOptions options) : mOptions(std::move(options)) {}
WindowSink::~WindowSink() = default;

void WindowSink::open(const StreamFormat& format) {
  const std::string problem = displayProblem();
  if (!problem.empty()) {
    throw std::runtime_error(
        "sinks.window: " + problem +
        " (run under a virtual display: xvfb-run -a fieldcast …, or set sinks.window.enabled = false)");
  }
  claimGuiThread();
  auto st = std::make_unique<State>();
  st->format = format;
  st->title = mOptions.title;
  st->picture = cv::Mat(format.heightPx, format.widthPx, CV_8UC3, cv::Scalar(0, 0, 0));
  try {
    cv::namedWindow(st->title, cv::WINDOW_NORMAL | cv::WINDOW_KEEPRATIO | cv::WINDOW_GUI_NORMAL);
    // Show the picture with its pixel aspect, so 720×486 at 10:11 looks 4:3
    const int shownWidth = format.widthPx * format.pixelAspect.numerator / format.pixelAspect.denominator;
    cv::resizeWindow(st->title, shownWidth, format.heightPx);
  } catch (const cv::Exception& e) {
    throw std::runtime_error("sinks.window: cannot open a window: " + std::string(e.what()));
  }
  mState = std::move(st);
}

SinkStatus WindowSink::consume(const Field& field) {
  State& st = *mState;
  for (int r = 0; r < field.image.heightPx(); ++r) {
    rowToRgb(field.image.row(r), field.image.format(), field.image.widthPx(),
             st.picture.ptr<std::uint8_t>(rasterRow(field.parity, r)), /*bgr=*/true);
  }
  const bool frameComplete = field.parity != st.format.firstParity() || field.parity == FieldParity::Progressive;
  try {
    if (frameComplete) {
      cv::Mat shown = st.picture;
      cv::Mat withOverlay;
      if (mOptions.overlay) {
        withOverlay = st.picture.clone();
        const WindowFigures f = mFigures.load();
        char line[96];
        std::snprintf(line, sizeof line, "render %.1f Hz", f.renderHz);
        drawText(withOverlay, line, 0);
        std::snprintf(line, sizeof line, "fields %llu", static_cast<unsigned long long>(f.fields));
        drawText(withOverlay, line, 1);
        std::snprintf(line, sizeof line, "missed %llu", static_cast<unsigned long long>(f.missedFields));
        drawText(withOverlay, line, 2);
        std::snprintf(line, sizeof line, "margin violations %llu", static_cast<unsigned long long>(f.marginViolations));
        drawText(withOverlay, line, 3);
        shown = withOverlay;
      }
      cv::imshow(st.title, shown);
    }
    // Pump the GUI and collect keys on every field
    for (int code = cv::waitKeyEx(1); code >= 0; code = cv::pollKey()) {
      if (mOptions.onKey) mOptions.onKey(code, decodeWindowKey(code));
    }
    if (cv::getWindowProperty(st.title, cv::WND_PROP_VISIBLE) < 1.0) {
      mEndReason = "the window was closed";
      return SinkStatus::Ended;
    }
  } catch (const cv::Exception& e) {
    mEndReason = std::string("window: ") + e.what();
    return SinkStatus::Ended;
  }
  ++mShown;
  return SinkStatus::Ok;
}

void WindowSink::close() {
  if (!mState) return;
  try {
    cv::destroyWindow(mState->title);
    cv::waitKey(1);
  } catch (const cv::Exception&) {
  }
  mState.reset();
}

}  // namespace fieldcast::io
