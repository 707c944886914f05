// Cost of the stick input path: HID report-descriptor parsing (once per device open), report
// decoding (once per report, up to 1 kHz), evdev frame decoding, mapping, and the field thread's
// lock-free read. The decode baseline is the bit-by-bit reference extraction, measured in the
// same run: run with --benchmark_repetitions=5 --benchmark_report_aggregates_only=true.
#include <io_bridge/EvdevDecoder.h>
#include <io_bridge/HidReportDecoder.h>
#include <io_bridge/HidReportDescriptor.h>
#include <io_bridge/StickInput.h>
#include <io_bridge/StickMapper.h>

#include "RealDescriptors.h"

#include <benchmark/benchmark.h>

#include <span>
#include <vector>

namespace {

using namespace fieldcast;
using namespace fieldcast::io;

struct Device {
  const char* name;
  std::span<const std::uint8_t> descriptor;
  std::size_t reportBytes;
};

const Device kDevices[] = {
    {"raptor_mach2", testdata::kRaptorMach2, 64},    {"tca_yoke", testdata::kTcaYokeBoeing, 64},
    {"saitek_ffb", testdata::kSaitekFfbJoystick, 7}, {"asus_gamepad", testdata::kAsusGamepad, 9},
    {"dualshock4", testdata::kDualShock4, 64},
};

std::vector<std::uint8_t> reportFor(const Device& d, int variant) {
  std::vector<std::uint8_t> r(d.reportBytes, 0x01);  // byte 0: report ID 1
  for (std::size_t i = 1; i < r.size(); ++i) r[i] = static_cast<std::uint8_t>((i * 29 + variant * 7) & 0xFF);
  return r;
}

void BM_ParseDescriptor(benchmark::State& state) {
  const Device& d = kDevices[state.range(0)];
  for (auto _ : state) {
    HidReportDescriptor parsed = parseHidReportDescriptor(d.descriptor);
    benchmark::DoNotOptimize(parsed);
  }
  state.SetLabel(d.name);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(d.descriptor.size()));
}
BENCHMARK(BM_ParseDescriptor)->DenseRange(0, 4);

void BM_DecodeReport(benchmark::State& state) {
  const Device& d = kDevices[state.range(0)];
  HidReportDecoder decoder(parseHidReportDescriptor(d.descriptor));
  const std::vector<std::uint8_t> report = reportFor(d, 0);
  for (auto _ : state) {
    const HidDecodeResult r = decoder.decode(report);
    benchmark::DoNotOptimize(r.values.data());
  }
  state.SetLabel(d.name);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_DecodeReport)->DenseRange(0, 4);

// Baseline: the same fields extracted one bit at a time (the test's reference).
void BM_DecodeReportBitByBit(benchmark::State& state) {
  const Device& d = kDevices[state.range(0)];
  const HidReportDescriptor parsed = parseHidReportDescriptor(d.descriptor);
  const std::vector<std::uint8_t> report = reportFor(d, 0);
  const std::span<const std::uint8_t> data = std::span<const std::uint8_t>(report).subspan(1);
  std::vector<std::int32_t> out(4096);
  for (auto _ : state) {
    std::size_t n = 0;
    for (const HidField& f : parsed.fields) {
      if (f.type != HidReportType::Input || f.reportId != 1 || f.isConstant()) continue;
      for (std::uint32_t e = 0; e < f.count; ++e) {
        std::uint32_t v = 0;
        for (std::uint32_t b = 0; b < std::min<std::uint32_t>(f.bitSize, 32); ++b) {
          const std::uint32_t bit = f.bitOffset + e * f.bitSize + b;
          v |= static_cast<std::uint32_t>((data[bit / 8] >> (bit % 8)) & 1u) << b;
        }
        out[n++] = static_cast<std::int32_t>(v);
      }
    }
    benchmark::DoNotOptimize(out.data());
  }
  state.SetLabel(d.name);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_DecodeReportBitByBit)->DenseRange(0, 4);

// Decode + change detection + events, alternating two reports so every control changes.
void BM_TranslateReport(benchmark::State& state) {
  const Device& d = kDevices[state.range(0)];
  HidInputTranslator translator(parseHidReportDescriptor(d.descriptor));
  const std::vector<std::uint8_t> a = reportFor(d, 0), b = reportFor(d, 1);
  std::vector<InputEvent> events;
  events.reserve(4096);
  std::int64_t t = 0;
  for (auto _ : state) {
    events.clear();
    translator.translate((t & 1) ? a : b, t, events);
    ++t;
    benchmark::DoNotOptimize(events.data());
  }
  state.SetLabel(d.name);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_TranslateReport)->DenseRange(0, 4);

// One evdev frame of a stick (X, Y, Rz, throttle, a button) through the decoder.
void BM_EvdevFrame(benchmark::State& state) {
  EvdevDecoder decoder(nullptr);
  std::vector<InputEvent> out;
  out.reserve(64);
  input_event frame[6]{};
  const std::uint16_t codes[5] = {ABS_X, ABS_Y, ABS_RZ, ABS_THROTTLE, BTN_TRIGGER};
  for (int i = 0; i < 5; ++i) {
    frame[i].type = i < 4 ? EV_ABS : EV_KEY;
    frame[i].code = codes[i];
  }
  frame[5].type = EV_SYN;
  frame[5].code = SYN_REPORT;
  std::int32_t v = 0;
  for (auto _ : state) {
    out.clear();
    ++v;
    for (int i = 0; i < 5; ++i) frame[i].value = i < 4 ? v : (v & 1);
    for (const input_event& e : frame) decoder.feed(e, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_EvdevFrame);

// Mapping one frame (4 axes, a button) to a ControlState through the generic profile.
void BM_MapFrame(benchmark::State& state) {
  DeviceDescription device;
  device.controls = {{usages::kX, ControlKind::Axis, 0, 1023},
                     {usages::kY, ControlKind::Axis, 0, 1023},
                     {usages::kRz, ControlKind::Axis, 0, 1023},
                     {usages::kThrottle, ControlKind::Axis, 0, 255},
                     {usages::button(1), ControlKind::Button, 0, 1}};
  StickProfile profile = StickProfile::generic();
  profile.axis(AxisRole::Roll).expo = 0.3;
  StickMapper mapper(device, profile);
  std::int32_t v = 0;
  for (auto _ : state) {
    ++v;
    mapper.apply({v, usages::kX, v & 1023, InputEventType::Value});
    mapper.apply({v, usages::kY, (v * 3) & 1023, InputEventType::Value});
    mapper.apply({v, usages::kRz, (v * 5) & 1023, InputEventType::Value});
    mapper.apply({v, usages::kThrottle, v & 255, InputEventType::Value});
    mapper.apply({v, usages::button(1), v & 1, InputEventType::Value});
    mapper.apply({v, 0, 0, InputEventType::Sync});
    benchmark::DoNotOptimize(mapper.state());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_MapFrame);

// What the field thread pays per field: a SeqLock load plus the loss decay.
void BM_FieldThreadRead(benchmark::State& state) {
  VirtualClock clock;
  StickInput input([]() -> std::unique_ptr<InputSource> { throw std::runtime_error("none"); }, StickProfile::generic(),
                   StickInputOptions{}, clock);
  TimePoint t{};
  for (auto _ : state) {
    t += Nanoseconds{16'683'333};
    const ControlState s = input.controlsAt(t);
    benchmark::DoNotOptimize(s);
  }
}
BENCHMARK(BM_FieldThreadRead);

}  // namespace

BENCHMARK_MAIN();
