#include <io_bridge/InputRecording.h>

#include <array>
#include <charconv>
#include <cinttypes>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace fieldcast::io {
namespace {

std::string_view kindWord(ControlKind k) {
  switch (k) {
    case ControlKind::Axis: return "axis";
    case ControlKind::Button: return "button";
    case ControlKind::Hat: return "hat";
  }
  return "axis";
}

}  // namespace

InputRecorder::InputRecorder(const std::filesystem::path& path, const DeviceDescription& device)
    : mPath(path), mOut(path, std::ios::trunc) {
  if (!mOut) throw std::runtime_error(path.string() + ": cannot create the input recording");
  std::array<char, 64> buf{};
  std::snprintf(buf.data(), buf.size(), "%04x %04x", device.vendorId, device.productId);
  mOut << "fieldcast-input 1\n";
  mOut << "device " << transportName(device.transport) << ' ' << buf.data() << ' ' << device.name << '\n';
  for (const ControlInfo& c : device.controls) {
    std::snprintf(buf.data(), buf.size(), "%08x", c.usage);
    mOut << "control " << buf.data() << ' ' << kindWord(c.kind) << ' ' << c.min << ' ' << c.max << '\n';
  }
}

void InputRecorder::write(std::span<const InputEvent> events) {
  std::array<char, 96> line{};
  for (const InputEvent& e : events) {
    int n = 0;
    switch (e.type) {
      case InputEventType::Value:
        n = std::snprintf(line.data(), line.size(), "v %" PRId64 " %08x %" PRId32 "\n", e.tNs, e.usage, e.value);
        break;
      case InputEventType::Sync: n = std::snprintf(line.data(), line.size(), "s %" PRId64 "\n", e.tNs); break;
      case InputEventType::DeviceLost: n = std::snprintf(line.data(), line.size(), "lost %" PRId64 "\n", e.tNs); break;
      case InputEventType::DeviceFound:
        n = std::snprintf(line.data(), line.size(), "found %" PRId64 "\n", e.tNs);
        break;
    }
    mOut.write(line.data(), n);
  }
  if (!mOut) throw std::runtime_error(mPath.string() + ": write failed");
}

void InputRecorder::flush() { mOut.flush(); }

namespace {

template <typename T>
bool number(std::string_view s, T& out, int base = 10) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out, base);
  return ec == std::errc{} && end == s.data() + s.size();
}

std::vector<std::string_view> split(std::string_view line, std::size_t maxParts) {
  std::vector<std::string_view> parts;
  while (!line.empty() && parts.size() + 1 < maxParts) {
    const auto sp = line.find(' ');
    parts.push_back(line.substr(0, sp));
    if (sp == std::string_view::npos) return parts;
    line.remove_prefix(sp + 1);
  }
  if (!line.empty()) parts.push_back(line);
  return parts;
}

}  // namespace

InputRecording readInputRecording(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot read the input recording");
  return parseInputRecording(in, path.string());
}

InputRecording parseInputRecording(std::istream& in, const std::string& origin) {
  InputRecording rec;
  std::string line;
  std::size_t lineNo = 0;
  bool header = false;
  auto fail = [&](const std::string& what) {
    throw std::runtime_error(origin + ":" + std::to_string(lineNo) + ": " + what);
  };
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      if (line != "fieldcast-input 1") fail("expected \"fieldcast-input 1\", got \"" + line + "\"");
      header = true;
      continue;
    }
    const auto p = split(line, line.rfind("device ", 0) == 0 ? 5 : 8);
    const std::string_view tag = p[0];
    if (tag == "device") {
      if (p.size() < 4) fail("expected \"device <transport> <vendor> <product> <name>\"");
      static const std::pair<std::string_view, InputTransport> kT[] = {{"evdev", InputTransport::Evdev},
                                                                       {"hidraw", InputTransport::Hidraw},
                                                                       {"usb", InputTransport::Usb},
                                                                       {"replay", InputTransport::Replay},
                                                                       {"fake", InputTransport::Fake}};
      bool known = false;
      for (const auto& [w, t] : kT) {
        if (p[1] == w) {
          rec.device.transport = t;
          known = true;
        }
      }
      if (!known) fail("unknown transport \"" + std::string(p[1]) + "\"");
      if (!number(p[2], rec.device.vendorId, 16) || !number(p[3], rec.device.productId, 16)) {
        fail("expected hexadecimal vendor and product IDs");
      }
      rec.device.name = p.size() > 4 ? std::string(p[4]) : std::string();
    } else if (tag == "control") {
      ControlInfo c;
      if (p.size() != 5 || !number(p[1], c.usage, 16) || !number(p[3], c.min) || !number(p[4], c.max)) {
        fail("expected \"control <usage hex> <axis|button|hat> <min> <max>\"");
      }
      if (p[2] == "axis") {
        c.kind = ControlKind::Axis;
      } else if (p[2] == "button") {
        c.kind = ControlKind::Button;
      } else if (p[2] == "hat") {
        c.kind = ControlKind::Hat;
      } else {
        fail("control kind must be axis, button or hat, got \"" + std::string(p[2]) + "\"");
      }
      rec.device.controls.push_back(c);
    } else if (tag == "v") {
      InputEvent e;
      if (p.size() != 4 || !number(p[1], e.tNs) || !number(p[2], e.usage, 16) || !number(p[3], e.value)) {
        fail("expected \"v <t_ns> <usage hex> <value>\"");
      }
      rec.events.push_back(e);
    } else if (tag == "s" || tag == "lost" || tag == "found") {
      InputEvent e;
      e.type = tag == "s"      ? InputEventType::Sync
               : tag == "lost" ? InputEventType::DeviceLost
                               : InputEventType::DeviceFound;
      if (p.size() != 2 || !number(p[1], e.tNs)) fail("expected \"" + std::string(tag) + " <t_ns>\"");
      rec.events.push_back(e);
    } else {
      fail("unknown record \"" + std::string(tag) + "\" (expected device, control, v, s, lost or found)");
    }
  }
  if (!header) throw std::runtime_error(origin + ": empty file, expected \"fieldcast-input 1\"");
  return rec;
}

ReplaySource::ReplaySource(InputRecording recording, ReplayPacing pacing, Clock& clock)
    : mRecording(std::move(recording)), mPacing(pacing), mClock(clock) {
  mRecording.device.transport = InputTransport::Replay;
}

ReplaySource::ReplaySource(const std::filesystem::path& path, ReplayPacing pacing, Clock& clock)
    : ReplaySource(readInputRecording(path), pacing, clock) {}

ReadResult ReplaySource::read(std::vector<InputEvent>& out, Nanoseconds timeout) {
  // Skip found markers: the source being open is the "found".
  while (mNext < mRecording.events.size() && mRecording.events[mNext].type == InputEventType::DeviceFound) ++mNext;
  if (mNext >= mRecording.events.size()) return ReadResult::End;
  const InputEvent& first = mRecording.events[mNext];
  if (first.type == InputEventType::DeviceLost) {
    ++mNext;
    return ReadResult::Lost;
  }
  if (mPacing == ReplayPacing::RealTime) {
    if (!mStarted) {
      mShiftNs = mClock.now().time_since_epoch().count() - first.tNs;
      mStarted = true;
    }
    // The frame is due when its Sync is.
    std::size_t end = mNext;
    while (end < mRecording.events.size() && mRecording.events[end].type == InputEventType::Value) ++end;
    const std::int64_t syncNs = end < mRecording.events.size() ? mRecording.events[end].tNs : first.tNs;
    const TimePoint due{Nanoseconds{syncNs + mShiftNs}};
    const TimePoint limit = mClock.now() + timeout;
    if (due > limit) {
      mClock.sleepUntil(limit);
      return ReadResult::Timeout;
    }
    mClock.sleepUntil(due);
  }
  // Deliver one frame: values up to and including the Sync.
  while (mNext < mRecording.events.size()) {
    InputEvent e = mRecording.events[mNext];
    if (e.type == InputEventType::DeviceLost || e.type == InputEventType::DeviceFound) break;
    ++mNext;
    e.tNs += mShiftNs;
    out.push_back(e);
    if (e.type == InputEventType::Sync) {
      ++mFrames;
      break;
    }
  }
  return ReadResult::Events;
}

}  // namespace fieldcast::io
