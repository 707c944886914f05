#include <io_bridge/StickProfile.h>

#include <toml++/toml.h>

#include <cctype>
#include <charconv>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

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

// Strict reading of one table: every key must be known, errors name file:line and the key.
class Reader {
 public:
  Reader(const std::string& origin, const toml::table& table, std::string prefix)
      : mOrigin(origin), mTable(table), mPrefix(std::move(prefix)) {}

  [[noreturn]] void fail(const toml::node& n, std::string_view key, const std::string& what) const {
    std::ostringstream os;
    os << mOrigin << ":" << n.source().begin.line << ": " << mPrefix << key << ": " << what;
    throw std::runtime_error(os.str());
  }
  const toml::node* get(std::string_view key) {
    mKnown.insert(std::string(key));
    return mTable.get(key);
  }
  double number(std::string_view key, double fallback, double lo, double hi) {
    const toml::node* n = get(key);
    if (n == nullptr) return fallback;
    const auto v = n->value<double>();
    if (!v || *v < lo || *v > hi) {
      fail(*n, key, "expected a number from " + fmt(lo) + " to " + fmt(hi) + ", got " + show(*n));
    }
    return *v;
  }
  std::optional<std::int32_t> integer(std::string_view key) {
    const toml::node* n = get(key);
    if (n == nullptr) return std::nullopt;
    const auto v = n->value<std::int64_t>();
    if (!n->is_integer() || !v || *v < INT32_MIN || *v > INT32_MAX)
      fail(*n, key, "expected an integer, got " + show(*n));
    return static_cast<std::int32_t>(*v);
  }
  bool boolean(std::string_view key, bool fallback) {
    const toml::node* n = get(key);
    if (n == nullptr) return fallback;
    if (!n->is_boolean()) fail(*n, key, "expected true or false, got " + show(*n));
    return *n->value<bool>();
  }
  void finish() const {
    for (const auto& [k, v] : mTable) {
      if (!mKnown.contains(std::string(k.str()))) fail(v, k.str(), "unknown key");
    }
  }
  static std::string show(const toml::node& n) {
    if (const auto s = n.value<std::string>(); s && n.is_string()) return "\"" + *s + "\"";
    std::ostringstream os;
    n.visit([&](auto&& x) { os << x; });
    return os.str();
  }
  static std::string fmt(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  }

 private:
  const std::string& mOrigin;
  const toml::table& mTable;
  std::string mPrefix;
  std::set<std::string> mKnown;
};

AxisBinding readAxis(const std::string& origin, const toml::table& t, std::string_view role, AxisBinding b) {
  Reader r(origin, t, std::string(role) + ".");
  if (const toml::node* n = r.get("control")) {
    std::vector<std::string> names;
    if (const auto s = n->value<std::string>()) {
      names.push_back(*s);
    } else if (const toml::array* a = n->as_array()) {
      for (const toml::node& e : *a) {
        const auto s2 = e.value<std::string>();
        if (!s2) r.fail(e, "control", "expected control names, got " + Reader::show(e));
        names.push_back(*s2);
      }
    } else {
      r.fail(*n, "control", "expected a control name or a list of names, got " + Reader::show(*n));
    }
    b.controls.clear();
    for (const std::string& name : names) {
      if (name == "none") continue;
      const Usage u = parseControlName(name);
      if (u == 0) {
        r.fail(*n, "control",
               "expected x, y, z, rx, ry, rz, slider, dial, wheel, throttle, rudder, accelerator, brake, steering, "
               "\"usage:0xPAGE:0xID\", \"abs:N\" or \"none\", got \"" +
                   name + "\"");
      }
      b.controls.push_back(u);
    }
  }
  b.invert = r.boolean("invert", b.invert);
  if (auto v = r.integer("min")) b.min = v;
  if (auto v = r.integer("max")) b.max = v;
  if (auto v = r.integer("center")) b.center = v;
  b.deadZone = r.number("dead_zone", b.deadZone, 0.0, 0.5);
  b.expo = r.number("expo", b.expo, 0.0, 1.0);
  if (b.min && b.max && *b.min >= *b.max)
    r.fail(*t.get("max"), "max", "expected more than min (" + std::to_string(*b.min) + ")");
  if (b.center && ((b.min && *b.center <= *b.min) || (b.max && *b.center >= *b.max))) {
    r.fail(*t.get("center"), "center", "expected a value strictly between min and max");
  }
  r.finish();
  return b;
}

}  // namespace

StickProfile parseStickProfile(std::string_view text, const std::string& origin) {
  toml::table root;
  try {
    root = toml::parse(text, origin);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << origin << ":" << e.source().begin.line << ": " << e.description();
    throw std::runtime_error(os.str());
  }
  StickProfile p = StickProfile::generic();
  Reader top(origin, root, "");
  if (const toml::node* n = top.get("name")) {
    const auto s = n->value<std::string>();
    if (!s || s->empty()) top.fail(*n, "name", "expected a non-empty string");
    p.name = *s;
  }
  if (const toml::node* n = top.get("match")) {
    const toml::array* a = n->as_array();
    if (a == nullptr) top.fail(*n, "match", "expected a list of device-name substrings");
    for (const toml::node& e : *a) {
      const auto s = e.value<std::string>();
      if (!s) top.fail(e, "match", "expected strings, got " + Reader::show(e));
      p.match.push_back(*s);
    }
  }
  p.defaultThrottle = top.number("default_throttle", p.defaultThrottle, 0.0, 1.0);
  for (std::size_t i = 0; i < kAxisRoles; ++i) {
    const auto role = static_cast<AxisRole>(i);
    const std::string_view name = axisRoleName(role);
    const toml::node* n = top.get(name);
    if (n == nullptr) continue;
    const toml::table* t = n->as_table();
    if (t == nullptr) top.fail(*n, name, "expected a table [" + std::string(name) + "]");
    p.axes[i] = readAxis(origin, *t, name, p.axes[i]);
  }
  if (const toml::node* n = top.get("buttons")) {
    const toml::table* t = n->as_table();
    if (t == nullptr) top.fail(*n, "buttons", "expected a table [buttons]");
    Reader r(origin, *t, "buttons.");
    if (const toml::node* o = r.get("order")) {
      const toml::array* a = o->as_array();
      if (a == nullptr) r.fail(*o, "order", "expected a list of device button numbers");
      if (a->size() > 64) r.fail(*o, "order", "expected at most 64 buttons, got " + std::to_string(a->size()));
      for (const toml::node& e : *a) {
        const auto v = e.value<std::int64_t>();
        if (!e.is_integer() || !v || *v < 1 || *v > 0xFFFF)
          r.fail(e, "order", "expected button numbers from 1, got " + Reader::show(e));
        p.buttonOrder.push_back(static_cast<std::uint16_t>(*v));
      }
    }
    r.finish();
  }
  if (const toml::node* n = top.get("loss")) {
    const toml::table* t = n->as_table();
    if (t == nullptr) top.fail(*n, "loss", "expected a table [loss]");
    Reader r(origin, *t, "loss.");
    p.lossDecayS = r.number("decay_s", p.lossDecayS, 0.0, 60.0);
    if (const toml::node* th = r.get("throttle")) {
      const auto s = th->value<std::string>();
      if (s && *s == "hold") {
        p.throttleOnLoss = ThrottleOnLoss::Hold;
      } else if (s && *s == "neutral") {
        p.throttleOnLoss = ThrottleOnLoss::Neutral;
      } else {
        r.fail(*th, "throttle", "expected \"hold\" or \"neutral\", got " + Reader::show(*th));
      }
    }
    r.finish();
  }
  top.finish();
  return p;
}

StickProfile loadStickProfile(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot read the stick profile");
  std::ostringstream text;
  text << in.rdbuf();
  return parseStickProfile(text.str(), path.string());
}

}  // namespace fieldcast::io
