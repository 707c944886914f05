#include "ConfigReader.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace fieldcast::app {
namespace {

std::string describe(const toml::node& node) {
  std::ostringstream s;
  node.visit([&](const auto& v) { s << v; });
  return s.str();
}

}  // namespace

ConfigReader::ConfigReader(std::string file, const toml::table* table, std::string prefix)
    : mFile(std::move(file)), mTable(table), mPrefix(std::move(prefix)) {}

std::string ConfigReader::where(const toml::node& node) const {
  // A value from --set has no source file: say so instead of pointing into the file.
  if (!node.source().path) return "--set";
  std::string s = *node.source().path;
  if (node.source().begin.line > 0) {
    s += ':';
    s += std::to_string(node.source().begin.line);
  }
  return s;
}

void ConfigReader::fail(const toml::node& node, const std::string& key, const std::string& what) const {
  throw ConfigError(where(node) + ": " + mPrefix + key + ": " + what + ", got " + describe(node));
}

void ConfigReader::fail(const std::string& key, const std::string& what) const {
  std::string location = mFile;
  if (mTable && mTable->source().begin.line > 0) location += ":" + std::to_string(mTable->source().begin.line);
  throw ConfigError(location + ": " + mPrefix + key + ": " + what);
}

const toml::node* ConfigReader::take(const char* key) {
  mRead.insert(key);
  return mTable ? mTable->get(key) : nullptr;
}

bool ConfigReader::has(const char* key) const { return mTable && mTable->contains(key); }

double ConfigReader::number(const char* key, double fallback, double min, double max) {
  const toml::node* n = take(key);
  if (!n) return fallback;
  const auto v = n->value<double>();
  if (!(n->is_number()) || !v || !std::isfinite(*v) || *v < min || *v > max) {
    std::ostringstream s;
    s << "expected a number from " << min << " to " << max;
    fail(*n, key, s.str());
  }
  return *v;
}

std::int64_t ConfigReader::integer(const char* key, std::int64_t fallback, std::int64_t min, std::int64_t max) {
  const toml::node* n = take(key);
  if (!n) return fallback;
  const auto v = n->value<std::int64_t>();
  if (!n->is_integer() || !v || *v < min || *v > max) {
    fail(*n, key, "expected an integer from " + std::to_string(min) + " to " + std::to_string(max));
  }
  return *v;
}

bool ConfigReader::boolean(const char* key, bool fallback) {
  const toml::node* n = take(key);
  if (!n) return fallback;
  if (!n->is_boolean()) fail(*n, key, "expected true or false");
  return *n->value<bool>();
}

std::string ConfigReader::string(const char* key, const std::string& fallback) {
  const toml::node* n = take(key);
  if (!n) return fallback;
  if (!n->is_string()) fail(*n, key, "expected a string");
  return *n->value<std::string>();
}

std::filesystem::path ConfigReader::path(const char* key, const std::filesystem::path& fallback) {
  const toml::node* n = take(key);
  std::string text;
  bool fromFile = true;
  if (n) {
    if (!n->is_string()) fail(*n, key, "expected a path string");
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
  const toml::node* n = take(key);
  if (!n) return fallback;
  const toml::array* a = n->as_array();
  const std::string expected = "expected an array of " + std::to_string(count) + " numbers";
  if (!a || a->size() != count) fail(*n, key, expected);
  std::vector<double> out;
  for (const auto& e : *a) {
    const auto v = e.value<double>();
    if (!e.is_number() || !v || !std::isfinite(*v)) fail(*n, key, expected);
    out.push_back(*v);
  }
  return out;
}

ConfigReader ConfigReader::table(const char* key) {
  const toml::node* n = take(key);
  if (n && !n->is_table()) fail(*n, key, "expected a table");
  return ConfigReader(mFile, n ? n->as_table() : nullptr, mPrefix + key + ".");
}

void ConfigReader::finish() const {
  if (!mTable) return;
  for (const auto& [key, node] : *mTable) {
    const std::string k(key.str());
    if (mRead.contains(k)) continue;
    std::string known;
    for (const auto& r : mRead) known += (known.empty() ? "" : ", ") + r;
    throw ConfigError(where(node) + ": " + mPrefix + k + ": unknown key (expected one of: " + known + ")");
  }
}

toml::table parseConfigFile(const std::string& path, const std::vector<std::string>& overrides) {
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << path << ':' << e.source().begin.line << ": " << e.description();
    throw ConfigError(s.str());
  }
  for (const auto& assignment : overrides) {
    const auto eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0) throw ConfigError("--set " + assignment + ": expected table.key=value");
    std::string keyPath = assignment.substr(0, eq);
    const std::string value = assignment.substr(eq + 1);
    toml::table parsed;
    try {
      parsed = toml::parse("v = " + value);
    } catch (const toml::parse_error&) {
      parsed = toml::parse("v = \"" + value + "\"");  // a bare word is a string: --set output.scan=progressive
    }
    // Walk (creating) the tables of a.b.c, then set the last key.
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
  return root;
}

}  // namespace fieldcast::app
