// libFuzzer target for the HID report-descriptor parser and report decoder.
// Input layout: 2 bytes little-endian descriptor length L, L descriptor bytes, then one report.
// Besides "no crash, no sanitizer report", it checks that every parsed field lies inside its
// report and that decoding never reads past the bytes it was given.
#include <io_bridge/HidReportDecoder.h>
#include <io_bridge/HidReportDescriptor.h>

#include "FuzzSeedCorpus.h"
#include "RealDescriptors.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <vector>

namespace {

using namespace fieldcast::io;

void writeSeed(const std::filesystem::path& dir, const char* name, std::span<const std::uint8_t> desc,
               std::size_t reportBytes, std::uint8_t reportId) {
  std::vector<std::uint8_t> bytes{static_cast<std::uint8_t>(desc.size() & 0xFF),
                                  static_cast<std::uint8_t>(desc.size() >> 8)};
  bytes.insert(bytes.end(), desc.begin(), desc.end());
  for (std::size_t i = 0; i < reportBytes; ++i) bytes.push_back(static_cast<std::uint8_t>(i == 0 ? reportId : i * 7));
  std::ofstream(dir / name, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

// Seeds the corpus directory (the first non-flag argument) with the real descriptors.
extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  if (const auto dir = testdata::emptyCorpusDirectory(*argc, *argv)) {
    writeSeed(*dir, "raptor", testdata::kRaptorMach2, 64, 1);
    writeSeed(*dir, "tca", testdata::kTcaYokeBoeing, 64, 1);
    writeSeed(*dir, "saitek", testdata::kSaitekFfbJoystick, 7, 1);
    writeSeed(*dir, "asus", testdata::kAsusGamepad, 9, 1);
    writeSeed(*dir, "ds4", testdata::kDualShock4, 64, 1);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t length = std::min<std::size_t>(data[0] | (std::size_t{data[1]} << 8), size - 2);
  const std::span<const std::uint8_t> desc(data + 2, length);
  // Copy the report so AddressSanitizer catches any read past its end.
  const std::vector<std::uint8_t> report(data + 2 + length, data + size);
  try {
    const HidReportDescriptor d = parseHidReportDescriptor(desc);
    for (const HidField& f : d.fields) {
      const HidReportInfo* r = d.report(f.type, f.reportId);
      if (r == nullptr || std::uint64_t{f.bitOffset} + std::uint64_t{f.bitSize} * f.count > r->bitLength) {
        std::fprintf(stderr, "field outside its report\n");
        __builtin_trap();
      }
      if (f.isVariable() && f.usages.size() != f.count) __builtin_trap();
    }
    HidInputTranslator translator(d);
    std::vector<InputEvent> events;
    (void)translator.translate(report, 0, events);
    (void)translator.translate(report, 1, events);
  } catch (const HidDescriptorError&) {
    // Refused with a reason: the expected outcome for most inputs.
  }
  return 0;
}
