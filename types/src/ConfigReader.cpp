#include <fieldcast/ConfigReader.h>

#include <toml++/toml.h>

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace fieldcast {

struct ConfigDocument::Data {
  std::string file;
  toml::table root;
};

namespace {

const toml::table* asTable(const void* p) { return static_cast<const toml::table*>(p); }
const toml::node* asNode(const void* p) { return static_cast<const toml::node*>(p); }

std::string describe(const toml::node& node) {
  if (const auto s = node.value<std::string>(); s && node.is_string()) return "\"" + *s + "\"";
  std::ostringstream s;
  node.visit([&](const auto& v) { s << v; });
  return s.str();
}

std::string formatNumber(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

[[noreturn]] void throwParseError(const std::string& origin, const toml::parse_error& e) {
  std::ostringstream s;
  s << origin << ':' << e.source().begin.line << ": " << e.description();
  throw ConfigError(s.str());
}

// Applies one "a.b.c=value" override, creating the tables on the way.
void applyOverride(toml::table& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) throw ConfigError("--set " + assignment + ": expected table.key=value");
  const std::string keyPath = assignment.substr(0, eq);
  const std::string value = assignment.substr(eq + 1);
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    parsed = toml::parse("v = \"" + value + "\"");  // a bare word is a string: --set output.scan=progressive
  }
  toml::table* table = &root;
  std::size_t start = 0;
  for (std::size_t dot = keyPath.find('.'); dot != std::string::npos; dot = keyPath.find('.', start)) {
    const std::string part = keyPath.substr(start, dot - start);
    if (part.empty()) throw ConfigError("--set " + assignment + ": empty key name");
    if (!table->contains(part)) table->insert(part, toml::table{});
    table = (*table)[part].as_table();
    if (!table) throw ConfigError("--set " + assignment + ": " + part + " is not a table");
    start = dot + 1;
  }
  const std::string last = keyPath.substr(start);
  if (last.empty()) throw ConfigError("--set " + assignment + ": empty key name");
  table->insert_or_assign(last, *parsed.get("v"));
}

}  // namespace

ConfigDocument ConfigDocument::parseFile(const std::filesystem::path& path, const std::vector<std::string>& overrides) {
  auto data = std::make_shared<Data>();
  data->file = path.string();
  try {
    data->root = toml::parse_file(data->file);
  } catch (const toml::parse_error& e) {
    throwParseError(data->file, e);
  }
  for (const auto& assignment : overrides) applyOverride(data->root, assignment);
  return ConfigDocument(std::move(data));
}

ConfigDocument ConfigDocument::parseText(std::string_view text, const std::string& origin) {
  auto data = std::make_shared<Data>();
  data->file = origin;
  try {
    data->root = toml::parse(text, origin);
  } catch (const toml::parse_error& e) {
    throwParseError(origin, e);
  }
  return ConfigDocument(std::move(data));
}

ConfigReader ConfigDocument::root() const { return ConfigReader(mData, mData->file, &mData->root, ""); }

ConfigReader::ConfigReader(std::shared_ptr<const void> owner, std::string file, const void* table, std::string prefix)
    : mOwner(std::move(owner)), mFile(std::move(file)), mTable(table), mPrefix(std::move(prefix)) {}

namespace {

// "file:line" of a node; a value from --set has no source file: say so instead of pointing into the file.
std::string locate(const toml::node& n) {
  if (!n.source().path) return "--set";
  std::string where = *n.source().path;
  if (n.source().begin.line > 0) where += ":" + std::to_string(n.source().begin.line);
  return where;
}

}  // namespace

void ConfigReader::failAt(const void* node, const std::string& key, const std::string& what) const {
  const toml::node& n = *asNode(node);
  throw ConfigError(locate(n) + ": " + mPrefix + key + ": " + what + ", got " + describe(n));
}

void ConfigReader::fail(const char* key, const std::string& what) const {
  if (const toml::node* n = mTable ? asTable(mTable)->get(key) : nullptr) failAt(n, key, what);
  std::string location = mFile;
  if (mTable && asTable(mTable)->source().begin.line > 0) {
    location += ":" + std::to_string(asTable(mTable)->source().begin.line);
  }
  throw ConfigError(location + ": " + mPrefix + key + ": " + what);
}

const void* ConfigReader::take(const char* key) {
  mRead.insert(key);
  return mTable ? asTable(mTable)->get(key) : nullptr;
}

bool ConfigReader::has(const char* key) const { return mTable && asTable(mTable)->contains(key); }

double ConfigReader::number(const char* key, double fallback, double min, double max) {
  const toml::node* n = asNode(take(key));
  if (!n) return fallback;
  const auto v = n->value<double>();
  if (!n->is_number() || !v || !std::isfinite(*v) || *v < min || *v > max) {
    failAt(n, key, "expected a number from " + formatNumber(min) + " to " + formatNumber(max));
  }
  return *v;
}

std::int64_t ConfigReader::integer(const char* key, std::int64_t fallback, std::int64_t min, std::int64_t max) {
  return optionalInteger(key, min, max).value_or(fallback);
}

std::optional<std::int64_t> ConfigReader::optionalInteger(const char* key, std::int64_t min, std::int64_t max) {
  const toml::node* n = asNode(take(key));
  if (!n) return std::nullopt;
  const auto v = n->value<std::int64_t>();
  if (!n->is_integer() || !v || *v < min || *v > max) {
    failAt(n, key, "expected an integer from " + std::to_string(min) + " to " + std::to_string(max));
  }
  return *v;
}

bool ConfigReader::boolean(const char* key, bool fallback) {
  const toml::node* n = asNode(take(key));
  if (!n) return fallback;
  if (!n->is_boolean()) failAt(n, key, "expected true or false");
  return *n->value<bool>();
}

std::string ConfigReader::string(const char* key, const std::string& fallback) {
  const toml::node* n = asNode(take(key));
  if (!n) return fallback;
  if (!n->is_string()) failAt(n, key, "expected a string");
  return *n->value<std::string>();
}

std::string ConfigReader::nonEmptyString(const char* key, const std::string& fallback) {
  std::string s = string(key, fallback);
  if (has(key) && s.empty()) fail(key, "expected a non-empty string");
  return s;
}

std::filesystem::path ConfigReader::path(const char* key, const std::filesystem::path& fallback) {
  const toml::node* n = asNode(take(key));
  std::string text;
  bool fromFile = true;
  if (n) {
    if (!n->is_string()) failAt(n, key, "expected a path string");
    text = *n->value<std::string>();
    fromFile = static_cast<bool>(n->source().path);
  } else {
    text = fallback.string();
  }
  if (text.empty()) return {};
  if (text.starts_with("~/")) {
    const char* home = std::getenv("HOME");  // NOLINT(concurrency-mt-unsafe): start-up only
    return std::filesystem::path(home ? home : "/tmp") / text.substr(2);
  }
  std::filesystem::path p(text);
  if (p.is_absolute() || !fromFile) return p;
  return std::filesystem::path(mFile).parent_path() / p;
}

std::vector<double> ConfigReader::numbers(const char* key, const std::vector<double>& fallback, std::size_t count) {
  const toml::node* n = asNode(take(key));
  if (!n) return fallback;
  const toml::array* a = n->as_array();
  const std::string expected = "expected an array of " + std::to_string(count) + " numbers";
  if (!a || a->size() != count) failAt(n, key, expected);
  std::vector<double> out;
  for (const auto& e : *a) {
    const auto v = e.value<double>();
    if (!e.is_number() || !v || !std::isfinite(*v)) failAt(n, key, expected);
    out.push_back(*v);
  }
  return out;
}

std::vector<std::int64_t> ConfigReader::integers(const char* key, std::int64_t min, std::int64_t max,
                                                 std::size_t maxCount) {
  const toml::node* n = asNode(take(key));
  if (!n) return {};
  const toml::array* a = n->as_array();
  const std::string expected = "expected an array of at most " + std::to_string(maxCount) + " integers from " +
                               std::to_string(min) + " to " + std::to_string(max);
  if (!a || a->size() > maxCount) failAt(n, key, expected);
  std::vector<std::int64_t> out;
  for (const auto& e : *a) {
    const auto v = e.value<std::int64_t>();
    if (!e.is_integer() || !v || *v < min || *v > max) failAt(&e, key, expected);
    out.push_back(*v);
  }
  return out;
}

std::optional<std::vector<std::string>> ConfigReader::strings(const char* key) {
  const toml::node* n = asNode(take(key));
  if (!n) return std::nullopt;
  if (n->is_string()) return std::vector<std::string>{*n->value<std::string>()};
  const toml::array* a = n->as_array();
  if (!a) failAt(n, key, "expected a string or an array of strings");
  std::vector<std::string> out;
  for (const auto& e : *a) {
    if (!e.is_string()) failAt(&e, key, "expected a string or an array of strings");
    out.push_back(*e.value<std::string>());
  }
  return out;
}

std::optional<std::string> ConfigReader::choiceWord(const char* key) {
  const toml::node* n = asNode(take(key));
  if (!n) return std::nullopt;
  // A value that is not a string matches no word: the caller's failure lists the words.
  return n->is_string() ? *n->value<std::string>() : std::string();
}

ConfigReader ConfigReader::table(const char* key) {
  const toml::node* n = asNode(take(key));
  if (n && !n->is_table()) failAt(n, key, "expected a table");
  return ConfigReader(mOwner, mFile, n ? n->as_table() : nullptr, mPrefix + key + ".");
}

std::vector<ConfigReader> ConfigReader::tables(const char* key) {
  const toml::node* n = asNode(take(key));
  if (!n) return {};
  const toml::array* a = n->as_array();
  if (!a) failAt(n, key, "expected tables [[" + std::string(key) + "]]");
  std::vector<ConfigReader> out;
  for (std::size_t i = 0; i < a->size(); ++i) {
    const toml::node& e = *a->get(i);
    if (!e.is_table()) failAt(&e, key, "expected tables [[" + std::string(key) + "]]");
    out.push_back(ConfigReader(mOwner, mFile, e.as_table(), mPrefix + key + "[" + std::to_string(i + 1) + "]."));
  }
  return out;
}

void ConfigReader::finish() const {
  if (!mTable) return;
  for (const auto& [key, node] : *asTable(mTable)) {
    const std::string k(key.str());
    if (mRead.contains(k)) continue;
    std::string known;
    for (const auto& r : mRead) known += (known.empty() ? "" : ", ") + r;
    throw ConfigError(locate(node) + ": " + mPrefix + k + ": unknown key (expected one of: " + known + ")");
  }
}

}  // namespace fieldcast
