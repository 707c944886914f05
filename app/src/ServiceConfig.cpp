#include "ServiceConfig.h"

#include <cmath>
#include <sstream>

namespace fieldcast::app {
namespace {

RationalRate readRate(ConfigReader& t) {
  const toml::node* n = t.raw("rate");
  if (!n) return {60000, 1001};
  const auto hz = n->value<double>();
  if (n->is_number() && hz) {
    if (std::abs(*hz - 59.94) < 1e-6) return {60000, 1001};
    if (*hz == 60.0) return {60, 1};
    if (*hz == 50.0) return {50, 1};
  }
  t.fail(*n, "rate", "expected 50, 59.94 or 60");
}

}  // namespace

ServiceConfig loadServiceConfig(const std::string& path, const std::vector<std::string>& overrides) {
  const toml::table root = parseConfigFile(path, overrides);
  ConfigReader top(path, &root, "");
  ServiceConfig c;
  c.sourcePath = path;

  {
    ConfigReader t = top.table("terrain");
    c.terrain.source = t.string("source", "builtin");
    if (c.terrain.source != "builtin") c.terrain.databasePath = t.path("source", "");
    // Empty: $FIELDCAST_CACHE_DIR, else $XDG_CACHE_HOME/fieldcast, else ~/.cache/fieldcast.
    if (!t.string("cache_dir", "").empty()) c.terrain.cacheDir = t.path("cache_dir", "");
    c.terrain.builtinSizeVoxels = static_cast<int>(t.integer("builtin_size", 8192, 256, 65536));
    if ((c.terrain.builtinSizeVoxels & (c.terrain.builtinSizeVoxels - 1)) != 0) {
      t.fail("builtin_size", "expected a power of two");
    }
    c.terrain.builtinSeed = static_cast<std::uint64_t>(t.integer("builtin_seed", 1, 0, INT64_MAX));
    c.terrain.memoryBudgetMiB = t.integer("memory_budget_mb", 1024, 16, 1 << 20);
    t.finish();
  }
  {
    ConfigReader t = top.table("output");
    c.output.fieldRate = readRate(t);
    c.output.scan = t.choice("scan", ScanMode::Interlaced,
                             {{"interlaced", ScanMode::Interlaced}, {"progressive", ScanMode::Progressive}});
    c.output.fieldOrder = t.choice("field_order", FieldOrder::BottomFirst,
                                   {{"top_first", FieldOrder::TopFirst}, {"bottom_first", FieldOrder::BottomFirst}});
    c.output.widthPx = static_cast<int>(t.integer("width", 720, 16, 8192));
    c.output.heightPx = static_cast<int>(t.integer("height", 486, 16, 8192));
    if (c.output.widthPx % 2 != 0) t.fail("width", "expected an even width (4:2:2 pairs pixels)");
    if (c.output.scan == ScanMode::Interlaced && c.output.heightPx % 2 != 0) {
      t.fail("height", "interlaced output needs an even height");
    }
    c.output.format =
        t.choice("format", PixelFormat::Uyvy422,
                 {{"uyvy422", PixelFormat::Uyvy422}, {"rgb8", PixelFormat::Rgb8}, {"grey8", PixelFormat::Grey8}});
    t.finish();
  }
  {
    ConfigReader t = top.table("render");
    c.render.threads = static_cast<int>(t.integer("threads", 0, 0, 256));
    c.render.maxRateHz = t.number("max_rate_hz", 0.0, 0.0, 1000.0);
    c.render.hfovDeg = t.number("fov_deg", 60.0, 5.0, 150.0);
    c.render.marginFraction = t.number("margin", 0.10, 0.0, 1.0);
    c.render.targetFrameMs = t.number("target_frame_ms", 0.0, 0.0, 1000.0);
    c.render.quality = t.number("quality", 1.0, 0.25, 16.0);
    c.render.maxAnisotropy = t.number("max_anisotropy", 0.0, 0.0, 64.0);
    c.render.controllerAnisotropy = t.number("controller_anisotropy", 2.0, 0.0, 64.0);
    c.render.rangeImage = t.boolean("range_image", false);
    c.render.grey = t.boolean("grey", false);
    c.render.widthPx = static_cast<int>(t.integer("width", c.output.widthPx, 16, 8192));
    c.render.heightPx = static_cast<int>(t.integer("height", c.output.heightPx, 16, 8192));
    t.finish();
  }
  {
    ConfigReader t = top.table("warp");
    c.warp.kind = t.choice("kind", WarpChoice::Quadratic,
                           {{"hold", WarpChoice::Hold},
                            {"quadratic", WarpChoice::Quadratic},
                            {"homography", WarpChoice::Homography},
                            {"range3d", WarpChoice::Range3d}});
    c.warp.flickerFilter = t.boolean("flicker_filter", false);
    c.warp.autoGain = t.boolean("auto_gain", false);
    c.warp.leadMs = t.number("lead_ms", 4.0, 0.5, 100.0);
    t.finish();
    if (c.warp.kind == WarpChoice::Range3d) c.render.rangeImage = true;  // the 3D warp needs range
  }
  {
    ConfigReader t = top.table("motion");
    c.motion.source =
        t.choice("source", MotionChoice::Flight, {{"flight", MotionChoice::Flight}, {"stick", MotionChoice::Stick}});
    c.motion.flightPath = t.path("flight", "flights/ridge_run.toml");
    c.motion.startPose = t.numbers("start", c.motion.startPose, 4);
    c.motion.startSpeedMps = t.number("start_speed_mps", 120.0, 0.0, 2000.0);
    c.motion.durationS = t.number("duration_s", 0.0, 0.0, 1e7);
    t.finish();
  }
  {
    ConfigReader sinks = top.table("sinks");
    {
      ConfigReader t = sinks.table("y4m");
      c.sinks.y4m.enabled = t.boolean("enabled", false);
      c.sinks.y4m.path = t.path("path", "fieldcast.y4m");
      c.sinks.y4m.chroma420 = t.choice("chroma", true, {{"420", true}, {"422", false}});
      t.finish();
    }
    {
      ConfigReader t = sinks.table("rtp");
      c.sinks.rtp.enabled = t.boolean("enabled", false);
      c.sinks.rtp.address = t.string("address", "127.0.0.1");
      c.sinks.rtp.port = static_cast<int>(t.integer("port", 5004, 1, 65535));
      c.sinks.rtp.mtu = static_cast<int>(t.integer("mtu", 1400, 576, 9000));
      c.sinks.rtp.sdpPath = t.path("sdp", "");
      t.finish();
    }
    {
      ConfigReader t = sinks.table("images");
      c.sinks.images.enabled = t.boolean("enabled", false);
      c.sinks.images.directory = t.path("directory", "fields");
      c.sinks.images.everyNth = static_cast<int>(t.integer("every_nth", 60, 1, 1 << 30));
      c.sinks.images.format =
          t.choice("format", std::string("png"), {{"png", std::string("png")}, {"exr", std::string("exr")}});
      t.finish();
    }
    {
      ConfigReader t = sinks.table("window");
      c.sinks.window.enabled = t.boolean("enabled", false);
      t.finish();
    }
    {
      ConfigReader t = sinks.table("shm");
      c.sinks.shm.enabled = t.boolean("enabled", false);
      c.sinks.shm.name = t.string("name", "/fieldcast");
      if (c.sinks.shm.name.size() < 2 || c.sinks.shm.name[0] != '/' ||
          c.sinks.shm.name.find('/', 1) != std::string::npos) {
        t.fail("name", "expected a POSIX shared-memory name like \"/fieldcast\"");
      }
      c.sinks.shm.slots = static_cast<int>(t.integer("slots", 4, 2, 64));
      t.finish();
    }
    {
      ConfigReader t = sinks.table("gpio_pulse");
      c.sinks.gpioPulse.enabled = t.boolean("enabled", false);
      c.sinks.gpioPulse.chip = t.string("chip", "gpiochip0");
      c.sinks.gpioPulse.line = static_cast<int>(t.integer("line", 0, 0, 1023));
      c.sinks.gpioPulse.widthUs = t.number("width_us", 500.0, 1.0, 10000.0);
      t.finish();
    }
    c.sinks.contactSheet = sinks.path("contact_sheet", "");
    c.sinks.contactSheetFields = static_cast<int>(sinks.integer("contact_sheet_fields", 12, 1, 100));
    sinks.finish();
  }
  {
    ConfigReader t = top.table("input");
    c.input.stick = t.string("stick", "");
    c.input.profile = t.path("profile", "");
    c.input.record = t.path("record", "");
    c.input.sync = t.string("sync", "");
    t.finish();
  }
  {
    ConfigReader t = top.table("metrics");
    c.metrics.logIntervalS = t.number("log_interval_s", 1.0, 0.1, 3600.0);
    c.metrics.summaryJson = t.path("summary_json", "");
    t.finish();
  }
  {
    ConfigReader t = top.table("threads");
    c.threads.realtimeFieldThread = t.boolean("realtime_field_thread", true);
    c.threads.fieldThreadCpu = static_cast<int>(t.integer("field_thread_cpu", -1, -1, 1023));
    t.finish();
  }
  top.finish();
  if (c.motion.source == MotionChoice::Stick && c.input.stick.empty() && !c.sinks.window.enabled) {
    top.fail("motion.source", "\"stick\" needs input.stick or sinks.window (keyboard flight)");
  }
  return c;
}

std::string describe(const ServiceConfig& c) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(3);
  s << c.sourcePath << ": output " << c.output.widthPx << "x" << c.output.heightPx << ' '
    << (c.output.scan == ScanMode::Interlaced ? "interlaced" : "progressive") << ' ' << c.output.fieldRate.hz()
    << " Hz " << toString(c.output.format) << "; render " << c.render.widthPx << "x" << c.render.heightPx << " fov "
    << c.render.hfovDeg << " deg; terrain " << c.terrain.source;
  return s.str();
}

}  // namespace fieldcast::app
