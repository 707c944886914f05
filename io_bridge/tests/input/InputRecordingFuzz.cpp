// libFuzzer target for the input-recording parser (recordings are files that travel between
// machines). Any input must either parse or be refused with a std::runtime_error; a parsed
// recording must replay without touching memory it does not own.
#include <io_bridge/InputRecording.h>

#include "FuzzSeedCorpus.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

// A clock that never sleeps: replay as fast as possible.
class NoClock final : public fieldcast::Clock {
 public:
  fieldcast::TimePoint now() const noexcept override { return fieldcast::TimePoint{}; }
  void sleepUntil(fieldcast::TimePoint) noexcept override {}
};

constexpr const char* kSeed =
    "fieldcast-input 1\n"
    "# seed\n"
    "device usb 06a3 ff0d Saitek Cyborg Force\n"
    "control 00010030 axis 0 255\n"
    "control 00090001 button 0 1\n"
    "control 00010039 hat 0 8\n"
    "v 1000 00010030 128\n"
    "v 1000 00010039 8\n"
    "s 1000\n"
    "v 5000 00090001 1\n"
    "s 5000\n"
    "lost 9000\n"
    "found 19000\n"
    "v 20000 00010030 -7\n"
    "s 20000\n";

}  // namespace

// Seeds an empty corpus directory (the first non-flag argument) with a valid recording.
extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  if (const auto dir = fieldcast::io::testdata::emptyCorpusDirectory(*argc, *argv)) {
    std::ofstream(*dir / "seed.rec") << kSeed;
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    fieldcast::io::InputRecording rec = fieldcast::io::parseInputRecording(in, "fuzz.rec");
    NoClock clock;
    fieldcast::io::ReplaySource source(std::move(rec), fieldcast::io::ReplayPacing::AsFastAsPossible, clock);
    std::vector<fieldcast::io::InputEvent> out;
    for (int i = 0; i < 10000; ++i) {
      const auto r = source.read(out, fieldcast::Nanoseconds{0});
      if (r == fieldcast::io::ReadResult::End) break;
    }
  } catch (const std::runtime_error&) {
    // Refused with a reason.
  }
  return 0;
}
