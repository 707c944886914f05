#include <service/ServiceConfig.h>

#include "ChannelView.h"

#include <fieldcast/Pose.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace fieldcast::app {
namespace {

ViewConfig readViewConfig(ConfigReader& t) {
  ViewConfig v;
  const std::vector<double> p = t.numbers("offset_m", {0.0, 0.0, 0.0}, 3);
  const std::vector<double> a = t.numbers("offset_deg", {0.0, 0.0, 0.0}, 3);
  v.offset.positionM = {p[0], p[1], p[2]};
  v.offset.headingRad = radians(a[0]);
  v.offset.pitchRad = radians(a[1]);
  v.offset.rollRad = radians(a[2]);
  if (t.has("frustum_deg")) {
    const std::vector<double> f = t.numbers("frustum_deg", {}, 4);
    const FrustumAngles angles{radians(f[0]), radians(f[1]), radians(f[2]), radians(f[3])};
    if (!angles.renderable()) {
      t.fail("frustum_deg",
             "expected [left, right, top, bottom] degrees, left below right and bottom below top, "
             "each from -80 to 80 (exclusive)");
    }
    v.frustum = angles;
  }
  v.eye = t.choice("eye", Eye::Centre, {{"centre", Eye::Centre}, {"left", Eye::Left}, {"right", Eye::Right}});
  v.eyeSeparationM = t.number("eye_separation_m", v.eyeSeparationM, 0.0, 10.0);
  if (t.has("convergence_m")) v.convergenceM = t.number("convergence_m", v.convergenceM, 0.1, 1e6);
  t.finish();
  return v;
}

io::FieldLockConfig readLockConfig(ConfigReader& t) {
  io::FieldLockConfig l;
  l.listen = t.string("listen", "");
  if (std::optional<std::vector<std::string>> peers = t.strings("peers")) l.peers = *peers;
  l.timeBase = t.choice("clock", io::LockTimeBase::Monotonic,
                        {{"monotonic", io::LockTimeBase::Monotonic}, {"tai", io::LockTimeBase::Tai}});
  const auto parsed = [&t](const char* key, const std::string& address) {
    try {
      return io::parseUdpAddress(address, key);
    } catch (const std::invalid_argument&) {
      t.fail(key, "expected \"address:port\" (IPv4), got \"" + address + "\"");
    }
  };
  if (!l.listen.empty()) (void)parsed("listen", l.listen);
  for (const std::string& peer : l.peers) {
    if (parsed("peers", peer).sin_port == 0) t.fail("peers", "a peer's port cannot be 0: \"" + peer + "\"");
    if (peer == l.listen) t.fail("peers", "this channel's own address (lock.listen) is not a peer: \"" + peer + "\"");
  }
  if (l.listen.empty() && !l.peers.empty())
    t.fail("listen", "the lock needs this channel's own address to hear its peers");
  t.finish();
  return l;
}

HostConfig readHostConfig(ConfigReader& t) {
  HostConfig h;
  h.link.listenAddress = t.nonEmptyString("listen_address", h.link.listenAddress);
  h.link.port = static_cast<std::uint16_t>(t.integer("port", h.link.port, 1, 65535));
  h.link.replyPort = static_cast<std::uint16_t>(t.integer("reply_port", h.link.replyPort, 0, 65535));
  h.databaseNumber = static_cast<std::int8_t>(t.integer("database_number", h.databaseNumber, 0, 127));
  h.viewId = static_cast<std::uint16_t>(t.integer("view_id", h.viewId, 0, 65535));
  h.viewGroup = static_cast<std::uint8_t>(t.integer("view_group", h.viewGroup, 0, 255));
  auto milliseconds = [&t](const char* key, Nanoseconds fallback, double max) {
    const double ms = t.number(key, std::chrono::duration<double, std::milli>(fallback).count(), 0.0, max);
    return std::chrono::duration_cast<Nanoseconds>(std::chrono::duration<double, std::milli>(ms));
  };
  h.motion.maxExtrapolation = milliseconds("max_extrapolation_ms", h.motion.maxExtrapolation, 10'000.0);
  h.motion.resumeBlend = milliseconds("resume_blend_ms", h.motion.resumeBlend, 10'000.0);
  const std::vector<double> origin = t.numbers("origin_deg", {h.origin.latitudeDeg, h.origin.longitudeDeg}, 2);
  if (std::abs(origin[0]) > 89.0 || std::abs(origin[1]) > 180.0) {
    t.fail("origin_deg", "expected [latitude within ±89, longitude within ±180]");
  }
  h.origin = {origin[0], origin[1]};
  h.celestialUtcOffsetH = t.number("celestial_utc_offset_h", h.celestialUtcOffsetH, -12.0, 14.0);
  for (ConfigReader& d : t.tables("database")) {
    HostDatabase database;
    if (!d.has("number")) d.fail("number", "expected the database's number (1 to 127)");
    database.number = static_cast<std::int8_t>(d.integer("number", 0, 1, 127));
    const bool taken = database.number == h.databaseNumber ||
                       std::any_of(h.databases.begin(), h.databases.end(),
                                   [&](const HostDatabase& other) { return other.number == database.number; });
    if (taken) d.fail("number", "expected a number no other database has (host.database_number is [terrain]'s)");
    database.terrain = core::readTerrainConfig(d);
    h.databases.push_back(std::move(database));
  }
  for (ConfigReader& m : t.tables("entity_model")) {
    HostEntityModel entity;
    if (!m.has("type") || !m.has("model"))
      m.fail("type", "expected the entity type (0 to 65535) and its model (a .vox file)");
    entity.type = static_cast<std::uint16_t>(m.integer("type", 0, 0, 65535));
    if (std::any_of(h.entityModels.begin(), h.entityModels.end(),
                    [&](const HostEntityModel& other) { return other.type == entity.type; })) {
      m.fail("type", "expected a type no other entity_model has");
    }
    entity.model = m.path("model", {});
    entity.scale = m.number("scale", 1.0, 0.25, 4.0);
    m.finish();
    h.entityModels.push_back(std::move(entity));
  }
  t.finish();
  return h;
}

}  // namespace

ServiceConfig loadServiceConfig(const std::string& path, const std::vector<std::string>& overrides) {
  ConfigReader top = ConfigDocument::parseFile(path, overrides).root();
  ServiceConfig c;
  c.sourcePath = path;
  auto section = [&top](const char* name, auto read) {
    ConfigReader t = top.table(name);
    return read(t);
  };
  c.terrain = section("terrain", core::readTerrainConfig);
  c.output = section("output", io::readStreamFormat);
  c.render = section("render",
                     [&](ConfigReader& t) { return core::readRenderConfig(t, c.output.widthPx, c.output.heightPx); });
  c.view = section("view", readViewConfig);
  // A stereo eye's window is the configured one shifted for the convergence: it must still be one
  // the renderer draws
  const ChannelView eyeView = channelViewOf(c.view, c.render.widthPx, c.render.heightPx, radians(c.render.hfovDeg));
  if (!eyeView.display.frustum().renderable()) {
    top.fail("view.convergence_m",
             "the eye's window, shifted to converge there, has an edge 80 degrees or more from "
             "its axis: converge farther, or narrow the window");
  }
  c.warp = section("warp", warp::readPrpSettings);
  if (c.warp.lead >= c.output.fieldRate.period()) {
    char expected[96];
    std::snprintf(expected, sizeof expected, "expected less than one field period (%.2f ms at %.2f Hz)",
                  toSeconds(c.output.fieldRate.period()) * 1e3, c.output.fieldRate.hz());
    top.table("warp").fail("lead_ms", expected);  // located at the key, its value shown
  }
  // The one place a warp's needs reach the renderer.
  if (warp::needsRangeImage(c.warp.warper.warp)) c.render.settings.rangeImage = true;
  c.motion = section("motion", motion::readMotionConfig);
  c.host = section("host", readHostConfig);
  c.lock = section("lock", readLockConfig);
  c.sinks = section("sinks", io::readSinksConfig);
  c.input = section("input", io::readInputConfig);
  if (!c.lock.listen.empty() && !c.input.sync.empty()) {
    top.fail("lock.listen", "a channel locks to the GPIO sync input (input.sync) or to the other channels, not both");
  }
  {
    ConfigReader t = top.table("metrics");
    c.metrics.logIntervalS = t.number("log_interval_s", 1.0, 0.1, 3600.0);
    c.metrics.summaryJson = t.path("summary_json", "");
    c.metrics.fieldLog = t.path("field_log", "");
    t.finish();
  }
  {
    ConfigReader t = top.table("threads");
    c.threads.realtimeFieldThread = t.boolean("realtime_field_thread", true);
    c.threads.realtimeHostThread = t.boolean("realtime_host_thread", true);
    c.threads.fieldThreadCpu = static_cast<int>(t.integer("field_thread_cpu", -1, -1, 1023));
    t.finish();
  }
  top.finish();
  if (c.motion.source == motion::MotionKind::Stick && c.input.stick.empty() && !c.sinks.window) {
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
    << " Hz " << toString(c.output.pixelFormat);
  constexpr const char* kMirrors[] = {"", " mirrored left-right", " mirrored top-bottom", " mirrored both ways"};
  s << kMirrors[static_cast<int>(c.warp.warper.mirror)] << "; render " << c.render.widthPx << "x" << c.render.heightPx;
  if (c.view.frustum) {
    s << " frustum " << degrees(c.view.frustum->leftRad) << "/" << degrees(c.view.frustum->rightRad) << "/"
      << degrees(c.view.frustum->topRad) << "/" << degrees(c.view.frustum->bottomRad) << " deg";
    // A window whose angles do not match the image's shape makes pixels that are not square
    const Intrinsics k = Intrinsics::fromFrustum(c.render.widthPx, c.render.heightPx, *c.view.frustum);
    if (std::abs(k.fxPx / k.fyPx - 1.0) > 0.005) s << " (pixels " << k.fxPx / k.fyPx << " wide for 1 high)";
  } else {
    s << " fov " << c.render.hfovDeg << " deg";
  }
  if (c.view.eye != Eye::Centre) {
    s << (c.view.eye == Eye::Left ? ", left eye " : ", right eye ") << c.view.eyeSeparationM << " m apart, ";
    if (std::isfinite(c.view.convergenceM)) {
      s << "converging at " << c.view.convergenceM << " m";
    } else {
      s << "axes parallel";
    }
  }
  s << "; terrain " << (c.terrain.database.empty() ? "builtin" : c.terrain.database.string());
  if (!c.lock.listen.empty()) {
    s << "; frame lock on " << c.lock.listen << " with " << c.lock.peers.size() << " peers"
      << (c.lock.timeBase == io::LockTimeBase::Tai ? " on CLOCK_TAI" : "");
  }
  return s.str();
}

}  // namespace fieldcast::app
