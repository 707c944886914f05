#include <io_bridge/SinksConfig.h>

#include <io_bridge/ContactSheetSink.h>
#include <io_bridge/ShmRing.h>

#include <cmath>
#include <stdexcept>

namespace fieldcast::io {
namespace {

RationalRate readRate(ConfigReader& t) {
  if (!t.has("rate")) return {60000, 1001};
  const double hz = t.number("rate", 59.94, 0.0, 1000.0);
  if (std::abs(hz - 59.94) < 1e-6) return {60000, 1001};
  if (hz == 60.0) return {60, 1};
  if (hz == 50.0) return {50, 1};
  t.fail("rate", "expected 50, 59.94 or 60");
}

// Creates the folder a file will be written in; throws naming the key.
void createParent(const std::filesystem::path& path, const char* key) {
  if (path.empty() || path == "-" || !path.has_parent_path()) return;
  std::error_code error;
  std::filesystem::create_directories(path.parent_path(), error);
  if (error) {
    throw std::runtime_error(std::string(key) + ": cannot create folder " + path.parent_path().string() + ": " +
                             error.message());
  }
}

}  // namespace

StreamFormat readStreamFormat(ConfigReader& t) {
  StreamFormat f;
  f.fieldRate = readRate(t);
  f.scan = t.choice("scan", f.scan, {{"interlaced", ScanMode::Interlaced}, {"progressive", ScanMode::Progressive}});
  f.fieldOrder = t.choice("field_order", f.fieldOrder,
                          {{"top_first", FieldOrder::TopFirst}, {"bottom_first", FieldOrder::BottomFirst}});
  f.widthPx = static_cast<int>(t.integer("width", f.widthPx, 16, 8192));
  f.heightPx = static_cast<int>(t.integer("height", f.heightPx, 16, 8192));
  if (f.widthPx % 2 != 0) t.fail("width", "expected an even width (4:2:2 pairs pixels)");
  if (f.scan == ScanMode::Interlaced && f.heightPx % 2 != 0) t.fail("height", "interlaced output needs an even height");
  f.pixelFormat =
      t.choice("format", f.pixelFormat,
               {{"uyvy422", PixelFormat::Uyvy422}, {"rgb8", PixelFormat::Rgb8}, {"grey8", PixelFormat::Grey8}});
  t.finish();
  f.pixelAspect = defaultPixelAspect(f.widthPx, f.heightPx);
  f.validate();
  return f;
}

SinksConfig readSinksConfig(ConfigReader& sinks) {
  SinksConfig c;
  {
    ConfigReader t = sinks.table("y4m");
    Y4mSinkOptions o;
    const bool on = t.boolean("enabled", false);
    o.path = t.path("path", "fieldcast.y4m");
    o.chroma = t.choice("chroma", Y4mChroma::C420, {{"420", Y4mChroma::C420}, {"422", Y4mChroma::C422}});
    t.finish();
    if (on) c.y4m = o;
  }
  {
    ConfigReader t = sinks.table("rtp");
    RtpVideoSinkOptions o;
    const bool on = t.boolean("enabled", false);
    o.address = t.string("address", o.address);
    o.port = static_cast<int>(t.integer("port", o.port, 1, 65535));
    o.mtuBytes = static_cast<int>(t.integer("mtu", o.mtuBytes, 576, 9000));
    o.sdpPath = t.path("sdp", "");  // what a receiver (ffplay, GStreamer) opens
    t.finish();
    if (on) c.rtp = o;
  }
  {
    ConfigReader t = sinks.table("images");
    ImageFileSinkOptions o;
    const bool on = t.boolean("enabled", false);
    o.directory = t.path("directory", "fields");
    o.everyNth = static_cast<int>(t.integer("every_nth", o.everyNth, 1, 1 << 30));
    o.format = t.choice("format", o.format, {{"png", ImageFileFormat::Png}, {"exr", ImageFileFormat::Exr}});
    t.finish();
    if (on) c.images = o;
  }
  {
    ConfigReader t = sinks.table("window");
    c.window = t.boolean("enabled", false);
    t.finish();
  }
  {
    ConfigReader t = sinks.table("shm");
    ShmOutput o;
    const bool on = t.boolean("enabled", false);
    o.name = t.string("name", o.name);
    if (o.name.size() < 2 || o.name[0] != '/' || o.name.find('/', 1) != std::string::npos) {
      t.fail("name", "expected a POSIX shared-memory name like \"/fieldcast\"");
    }
    o.slots = static_cast<int>(t.integer("slots", o.slots, 2, 64));
    t.finish();
    if (on) c.shm = o;
  }
  {
    ConfigReader t = sinks.table("gpio_pulse");
    GpioPulseOutput o;
    const bool on = t.boolean("enabled", false);
    o.chip = t.string("chip", o.chip);
    o.line = static_cast<int>(t.integer("line", o.line, 0, 1023));
    o.pulse.width = fromSeconds(t.number("width_us", 500.0, 1.0, 10000.0) * 1e-6);
    t.finish();
    if (on) c.gpioPulse = o;
  }
  c.contactSheet = sinks.path("contact_sheet", "");
  c.contactSheetFields = static_cast<int>(sinks.integer("contact_sheet_fields", c.contactSheetFields, 1, 100));
  sinks.finish();
  return c;
}

Sinks makeSinks(const SinksConfig& config, const StreamFormat& format,
                std::function<void(int code, WindowKey key)> onKey) {
  Sinks result;
  // Four fields of slack per sink absorb a stall of 60 ms; the pool holds depth × sinks + 1 fields.
  result.hub = std::make_unique<SinkHub>(format, SinkHubOptions{4});
  SinkHub* hub = result.hub.get();
  if (config.y4m) {
    createParent(config.y4m->path, "sinks.y4m.path");
    hub->add(std::make_unique<Y4mSink>(*config.y4m));
  }
  if (config.rtp) hub->add(std::make_unique<RtpVideoSink>(*config.rtp));
  if (config.images) {
    std::error_code error;
    std::filesystem::create_directories(config.images->directory, error);
    if (error) {
      throw std::runtime_error("sinks.images.directory: cannot create " + config.images->directory.string() + ": " +
                               error.message());
    }
    hub->add(std::make_unique<ImageFileSink>(*config.images));
  }
  if (config.shm) hub->add(std::make_unique<ShmRingSink>(config.shm->name, config.shm->slots));
  if (config.gpioPulse) {
    auto line = std::make_unique<GpiodPulseLine>(config.gpioPulse->chip, static_cast<unsigned>(config.gpioPulse->line));
    // The pulse edges are the rig's field timing: its worker runs at real-time priority.
    hub->add(std::make_unique<GpioPulseSink>(std::move(line), config.gpioPulse->pulse), SinkWorkerOptions{60});
  }
  if (config.window) {
    if (const std::string problem = WindowSink::displayProblem(); !problem.empty()) {
      throw std::runtime_error("sinks.window: no live window: " + problem);
    }
    WindowSinkOptions options;
    options.onKey = std::move(onKey);
    auto window = std::make_unique<WindowSink>(std::move(options));
    result.window = window.get();
    hub->add(std::move(window));
  }
  if (!config.contactSheet.empty()) {
    createParent(config.contactSheet, "sinks.contact_sheet");
    // One candidate a second; the sheet picks its thumbnails evenly from them at the end.
    const int perSecond = static_cast<int>(format.fieldRate.hz() + 0.5);
    ContactSheetOptions options;
    options.path = config.contactSheet;
    options.thumbnails = config.contactSheetFields;
    options.keepEveryNth = perSecond;
    hub->add(std::make_unique<ContactSheetSink>(options));
  }
  return result;
}

}  // namespace fieldcast::io
