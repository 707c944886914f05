#include <io_bridge/StickProfile.h>

#include <fieldcast/ConfigReader.h>

#include <cctype>
#include <charconv>

namespace fieldcast::io {

std::string_view axisRoleName(AxisRole role) noexcept {
  switch (role) {
    case AxisRole::Roll: return "roll";
    case AxisRole::Pitch: return "pitch";
    case AxisRole::Yaw: return "yaw";
    case AxisRole::Throttle: return "throttle";
  }
  return "?";
}

StickProfile StickProfile::generic() {
  using namespace usages;
  StickProfile p;
  p.name = "generic";
  p.axis(AxisRole::Roll) = AxisBinding{{kX}, false, {}, {}, {}, 0.02, 0.0};
  p.axis(AxisRole::Pitch) = AxisBinding{{kY}, false, {}, {}, {}, 0.02, 0.0};
  p.axis(AxisRole::Yaw) = AxisBinding{{kRz, kRudder}, false, {}, {}, {}, 0.05, 0.0};
  p.axis(AxisRole::Throttle) = AxisBinding{{kThrottle, kSlider, kZ}, true, {}, {}, {}, 0.01, 0.0};
  return p;
}

namespace {

std::optional<std::uint32_t> parseNumber(std::string_view s) {
  int base = 10;
  if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
    s.remove_prefix(2);
    base = 16;
  }
  std::uint32_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v, base);
  if (ec != std::errc{} || end != s.data() + s.size()) return std::nullopt;
  return v;
}

}  // namespace

Usage parseControlName(std::string_view name) noexcept {
  using namespace usages;
  std::string n(name);
  for (char& c : n) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  static const std::pair<const char*, Usage> kNames[] = {{"x", kX},
                                                         {"y", kY},
                                                         {"z", kZ},
                                                         {"rx", kRx},
                                                         {"ry", kRy},
                                                         {"rz", kRz},
                                                         {"slider", kSlider},
                                                         {"dial", kDial},
                                                         {"wheel", kWheel},
                                                         {"hat", kHatSwitch},
                                                         {"throttle", kThrottle},
                                                         {"rudder", kRudder},
                                                         {"accelerator", kAccelerator},
                                                         {"brake", kBrake},
                                                         {"steering", kSteering}};
  for (const auto& [word, usage] : kNames) {
    if (n == word) return usage;
  }
  const std::string_view v(n);
  if (v.rfind("usage:", 0) == 0) {
    const auto colon = v.find(':', 6);
    if (colon == std::string_view::npos) return 0;
    const auto page = parseNumber(v.substr(6, colon - 6));
    const auto id = parseNumber(v.substr(colon + 1));
    if (!page || !id || *page > 0xFFFF || *id > 0xFFFF || *id == 0) return 0;
    return makeUsage(static_cast<std::uint16_t>(*page), static_cast<std::uint16_t>(*id));
  }
  if (v.rfind("abs:", 0) == 0) {
    const auto code = parseNumber(v.substr(4));
    if (!code || *code > 0x3F) return 0;
    return makeUsage(kEvdevAbsPage, static_cast<std::uint16_t>(*code));
  }
  return 0;
}

namespace {

const char* const kControlNames =
    "expected x, y, z, rx, ry, rz, slider, dial, wheel, throttle, rudder, accelerator, brake, steering, "
    "\"usage:0xPAGE:0xID\", \"abs:N\" or \"none\"";

AxisBinding readAxis(ConfigReader& r, AxisBinding b) {
  if (const auto names = r.strings("control")) {
    b.controls.clear();
    for (const std::string& name : *names) {
      if (name == "none") continue;
      const Usage u = parseControlName(name);
      if (u == 0) r.fail("control", kControlNames);
      b.controls.push_back(u);
    }
  }
  b.invert = r.boolean("invert", b.invert);
  if (auto v = r.optionalInteger("min", INT32_MIN, INT32_MAX)) b.min = static_cast<std::int32_t>(*v);
  if (auto v = r.optionalInteger("max", INT32_MIN, INT32_MAX)) b.max = static_cast<std::int32_t>(*v);
  if (auto v = r.optionalInteger("center", INT32_MIN, INT32_MAX)) b.center = static_cast<std::int32_t>(*v);
  b.deadZone = r.number("dead_zone", b.deadZone, 0.0, 0.5);
  b.expo = r.number("expo", b.expo, 0.0, 1.0);
  if (b.min && b.max && *b.min >= *b.max) r.fail("max", "expected more than min (" + std::to_string(*b.min) + ")");
  if (b.center && ((b.min && *b.center <= *b.min) || (b.max && *b.center >= *b.max))) {
    r.fail("center", "expected a value strictly between min and max");
  }
  r.finish();
  return b;
}

StickProfile readStickProfile(ConfigReader top) {
  StickProfile p = StickProfile::generic();
  p.name = top.nonEmptyString("name", p.name);
  if (const auto match = top.strings("match")) p.match = *match;
  p.defaultThrottle = top.number("default_throttle", p.defaultThrottle, 0.0, 1.0);
  for (std::size_t i = 0; i < kAxisRoles; ++i) {
    const std::string name(axisRoleName(static_cast<AxisRole>(i)));
    if (!top.has(name.c_str())) continue;
    ConfigReader axis = top.table(name.c_str());
    p.axes[i] = readAxis(axis, p.axes[i]);
  }
  {
    ConfigReader r = top.table("buttons");
    for (const std::int64_t b : r.integers("order", 1, 0xFFFF, 64))
      p.buttonOrder.push_back(static_cast<std::uint16_t>(b));
    const auto cockpitButton = [&r](const char* key) {
      return static_cast<int>(r.optionalInteger(key, 1, 64).value_or(0));
    };
    p.cockpit.freeze = cockpitButton("freeze");
    p.cockpit.reset = cockpitButton("reset");
    p.cockpit.trigger = cockpitButton("trigger");
    r.finish();
  }
  {
    ConfigReader r = top.table("loss");
    p.lossDecayS = r.number("decay_s", p.lossDecayS, 0.0, 60.0);
    p.throttleOnLoss =
        r.choice("throttle", p.throttleOnLoss, {{"hold", ThrottleOnLoss::Hold}, {"neutral", ThrottleOnLoss::Neutral}});
    r.finish();
  }
  top.finish();
  return p;
}

}  // namespace

StickProfile parseStickProfile(std::string_view text, const std::string& origin) {
  return readStickProfile(ConfigDocument::parseText(text, origin).root());
}

StickProfile loadStickProfile(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw ConfigError(path.string() + ": cannot read the stick profile");
  return readStickProfile(ConfigDocument::parseFile(path).root());
}

}  // namespace fieldcast::io
