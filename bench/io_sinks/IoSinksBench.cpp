// Cost per field of each field output at 720×486 interlaced (NTSC, UYVY) and 1920×1080
// progressive (UYVY). Arg 0 = 720×486i, 1 = 1920×1080p. The baseline is one memcpy of the field
// (BM_CopyField): every sink must at least read its field once; ratios are against it.
//
// Run: fieldcast_bench_io_sinks --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <io_bridge/GpioPulseSink.h>
#include <io_bridge/ImageFileSink.h>
#include <io_bridge/Rfc4175Packetizer.h>
#include <io_bridge/RtpVideoSink.h>
#include <io_bridge/ShmRing.h>
#include <io_bridge/SinkHub.h>
#include <io_bridge/WindowSink.h>
#include <io_bridge/Y4mSink.h>

#include <benchmark/benchmark.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <thread>
#include <vector>

namespace fieldcast::io {
namespace {

StreamFormat formatFor(std::int64_t which) {
  StreamFormat f;
  f.pixelFormat = PixelFormat::Uyvy422;
  if (which == 0) {
    f.widthPx = 720;
    f.heightPx = 486;
    f.scan = ScanMode::Interlaced;
    f.fieldOrder = FieldOrder::BottomFirst;
  } else {
    f.widthPx = 1920;
    f.heightPx = 1080;
    f.scan = ScanMode::Progressive;
  }
  f.pixelAspect = defaultPixelAspect(f.widthPx, f.heightPx);
  return f;
}

// Field k with a varied pattern (so PNG compression does real work).
Field fieldFor(const StreamFormat& f, std::uint64_t k) {
  Field field;
  field.parity = parityOfField(k, f.scan, f.fieldOrder);
  field.rasterHeightPx = f.heightPx;
  field.fieldNumber = k;
  field.image = Image(f.widthPx, f.fieldRows(field.parity), f.pixelFormat);
  for (int r = 0; r < field.image.heightPx(); ++r) {
    std::uint8_t* p = field.image.row(r);
    for (int x = 0; x < f.widthPx; ++x) {
      p[2 * x] = static_cast<std::uint8_t>(128 + ((x / 8 + r / 8) % 2 ? 30 : -30));
      p[2 * x + 1] = static_cast<std::uint8_t>(16 + (x * 219 / f.widthPx + r + static_cast<int>(k)) % 220);
    }
  }
  return field;
}

void label(benchmark::State& state, const StreamFormat& f, std::size_t fieldBytes) {
  state.SetLabel(f.widthPx == 720 ? "720x486i" : "1920x1080p");
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(fieldBytes));
  state.counters["fields/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

// Runs consume() on two alternating fields (a frame's worth for interlaced streams).
void consumeLoop(benchmark::State& state, FieldSink& sink, const StreamFormat& f) {
  const Field fields[2] = {fieldFor(f, 0), fieldFor(f, 1)};
  std::uint64_t k = 0;
  for (auto _ : state) {
    Field const& field = fields[k % 2];
    // field numbers advance so frame pairing and every-Nth logic behave as in service
    const_cast<Field&>(field).fieldNumber = k;
    if (sink.consume(field) != SinkStatus::Ok) state.SkipWithError("sink ended");
    ++k;
  }
  label(state, f, fields[0].image.bytes().size());
}

void BM_CopyField(benchmark::State& state) {
  const StreamFormat f = formatFor(state.range(0));
  const Field field = fieldFor(f, 0);
  Field copy = field;
  for (auto _ : state) {
    std::memcpy(copy.image.bytes().data(), field.image.bytes().data(), field.image.bytes().size());
    benchmark::ClobberMemory();
  }
  label(state, f, field.image.bytes().size());
}
BENCHMARK(BM_CopyField)->Arg(0)->Arg(1);

// The field thread's cost: SinkHub::publish to 1 or 4 sinks, with a free slot each time (the worker
// is let catch up outside the timed region), i.e. one field copy plus the hand-over.
class CountingSink final : public FieldSink {
 public:
  std::atomic<std::uint64_t> consumed{0};
  std::string name() const override { return "counting"; }
  void open(const StreamFormat&) override {}
  SinkStatus consume(const Field&) override {
    consumed.fetch_add(1, std::memory_order_release);
    return SinkStatus::Ok;
  }
  void close() override {}
};
void BM_HubPublish(benchmark::State& state) {
  const StreamFormat f = formatFor(state.range(0));
  SinkHub hub(f, SinkHubOptions{4});
  std::vector<CountingSink*> counters;
  for (std::int64_t i = 0; i < state.range(1); ++i) {
    auto sink = std::make_unique<CountingSink>();
    counters.push_back(sink.get());
    hub.add(std::move(sink));
  }
  hub.start();
  const Field fields[2] = {fieldFor(f, 0), fieldFor(f, 1)};
  std::uint64_t k = 0;
  for (auto _ : state) {
    hub.publish(fields[k++ % 2]);
    state.PauseTiming();
    for (CountingSink* c : counters) {
      while (c->consumed.load(std::memory_order_acquire) < k) std::this_thread::yield();
    }
    state.ResumeTiming();
  }
  hub.stop();
  label(state, f, fields[0].image.bytes().size());
  state.counters["dropped"] = static_cast<double>(hub.droppedTotal());
}
BENCHMARK(BM_HubPublish)->ArgsProduct({{0, 1}, {1, 4}});  // one sink, four sinks

// The field thread's cost with only a stills sink (the 1080i config's: a PNG every 300 fields):
// the fields it passes over are not copied (FieldSink::wants), against BM_HubPublish's one copy.
void BM_HubPublishStills(benchmark::State& state) {
  const StreamFormat f = formatFor(state.range(0));
  const auto dir = std::filesystem::temp_directory_path() / ("fieldcast_bench_stills_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  SinkHub hub(f, SinkHubOptions{3});
  hub.add(std::make_unique<ImageFileSink>(ImageFileSinkOptions{dir, 300, ImageFileFormat::Png, "bench"}));
  hub.start();
  Field fields[2] = {fieldFor(f, 0), fieldFor(f, 1)};
  std::uint64_t k = 0;
  for (auto _ : state) {
    Field& field = fields[k % 2];
    field.fieldNumber = k++;
    hub.publish(field);
    if (field.fieldNumber % 300 == 0) {
      // Fields come here far faster than at 59.94 Hz: let the still be written, untimed
      state.PauseTiming();
      while (hub.figures()[0].consumed < field.fieldNumber / 300 + 1) std::this_thread::yield();
      state.ResumeTiming();
    }
  }
  hub.stop();
  const SinkFigures figures = hub.figures()[0];
  std::filesystem::remove_all(dir);
  state.SetLabel(f.widthPx == 720 ? "720x486i" : "1920x1080p");  // no bytes/s: most fields are not copied
  state.counters["queued"] = static_cast<double>(figures.published - figures.passedOver);
  state.counters["dropped"] = static_cast<double>(hub.droppedTotal());
}
BENCHMARK(BM_HubPublishStills)->Arg(0)->Arg(1)->Iterations(3000);  // 10 stills a run

void BM_Y4m(benchmark::State& state) {
  const StreamFormat f = formatFor(state.range(0));
  Y4mSink sink({"/dev/null", state.range(1) == 420 ? Y4mChroma::C420 : Y4mChroma::C422});
  sink.open(f);
  consumeLoop(state, sink, f);
  sink.close();
}
BENCHMARK(BM_Y4m)->ArgsProduct({{0, 1}, {420, 422}});

void BM_RtpPacketize(benchmark::State& state) {
  const StreamFormat f = formatFor(state.range(0));
  const Field field = fieldFor(f, 0);
  Rfc4175Packetizer packer(f.widthPx, 1400, 96, 1);
  RtpPacketBatch batch;
  batch.reserve(packer.packetsFor(field.image.heightPx()), packer.maxPacketBytes());
  for (auto _ : state) {
    benchmark::DoNotOptimize(packer.packetize(field.image.bytes().data(), field.image.strideBytes(),
                                              field.image.heightPx(), RtpField::TopOrProgressive, 0, batch));
  }
  label(state, f, field.image.bytes().size());
  state.counters["packets"] = batch.count();
}
BENCHMARK(BM_RtpPacketize)->Arg(0)->Arg(1);

// Packetise and send to a loopback socket nobody reads (the kernel drops what overflows), with
// pacing off: the CPU cost of the sink, not the field period it spreads packets over.
void BM_RtpSend(benchmark::State& state) {
  const StreamFormat f = formatFor(state.range(0));
  const int rx = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(rx, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  getsockname(rx, reinterpret_cast<sockaddr*>(&a), &len);
  RtpVideoSinkOptions o;
  o.port = ntohs(a.sin_port);
  o.pacingFraction = 0.0;
  RtpVideoSink sink(o);
  sink.open(f);
  consumeLoop(state, sink, f);
  sink.close();
  state.counters["send_errors"] = static_cast<double>(sink.figures().sendErrors);
  ::close(rx);
}
BENCHMARK(BM_RtpSend)->Arg(0)->Arg(1);

void BM_ShmPublish(benchmark::State& state) {
  const StreamFormat f = formatFor(state.range(0));
  ShmRingWriter writer("/fieldcast_bench_" + std::to_string(::getpid()), f, 4);
  const Field fields[2] = {fieldFor(f, 0), fieldFor(f, 1)};
  std::uint64_t k = 0;
  for (auto _ : state) benchmark::DoNotOptimize(writer.publish(fields[k++ % 2]));
  label(state, f, fields[0].image.bytes().size());
}
BENCHMARK(BM_ShmPublish)->Arg(0)->Arg(1);

// Every field written (every_nth = 1): what one snapshot costs.
void BM_ImageFile(benchmark::State& state) {
  const StreamFormat f = formatFor(state.range(0));
  const auto dir = std::filesystem::temp_directory_path() / ("fieldcast_bench_images_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  ImageFileSink sink({dir, 1, state.range(1) == 0 ? ImageFileFormat::Png : ImageFileFormat::Exr, "bench"});
  sink.open(f);
  consumeLoop(state, sink, f);
  sink.close();
  std::filesystem::remove_all(dir);
  state.SetLabel(std::string(f.widthPx == 720 ? "720x486i" : "1920x1080p") + (state.range(1) == 0 ? " png" : " exr"));
}
BENCHMARK(BM_ImageFile)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond);

void BM_Window(benchmark::State& state) {
  const StreamFormat f = formatFor(state.range(0));
  if (!WindowSink::displayProblem().empty()) {
    state.SkipWithError("no display (run under xvfb-run -a)");
    return;
  }
  WindowSink sink({"bench", true, nullptr});
  sink.open(f);
  consumeLoop(state, sink, f);
  sink.close();
}
BENCHMARK(BM_Window)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The pulse in virtual time: the sink's own overhead (two line writes, two clock calls).
class NullLine final : public PulseLine {
 public:
  void set(bool high) noexcept override { benchmark::DoNotOptimize(high); }
  std::string describe() const override { return "null"; }
};
void BM_GpioPulse(benchmark::State& state) {
  const StreamFormat f = formatFor(state.range(0));
  auto clock = std::make_shared<VirtualClock>();
  GpioPulseSink sink(std::make_unique<NullLine>(), {}, clock);
  sink.open(f);
  Field field = fieldFor(f, 0);
  std::uint64_t k = 0;
  for (auto _ : state) {
    field.displayTime = TimePoint{f.fieldRate.tickOffset(static_cast<std::int64_t>(k++))};
    sink.consume(field);
  }
  label(state, f, 0);
}
BENCHMARK(BM_GpioPulse)->Arg(0)->Arg(1);

}  // namespace
}  // namespace fieldcast::io

BENCHMARK_MAIN();
