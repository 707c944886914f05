#include "ServiceConfig.h"

#include <toml++/toml.h>

#include <cmath>
#include <set>
#include <sstream>

namespace fieldcast::app {
namespace {

std::string where(const std::string& file, const toml::node& node) {
  std::ostringstream s;
  s << file;
  if (node.source().begin.line > 0) s << ':' << node.source().begin.line;
  return s.str();
}

[[noreturn]] void fail(const std::string& file, const toml::node& node, const std::string& key,
                       const std::string& what) {
  throw ConfigError(where(file, node) + ": " + key + ": " + what);
}

std::string describe(const toml::node& node) {
  std::ostringstream s;
  node.visit([&](const auto& v) { s << v; });
  return s.str();
}

// Rejects keys the schema does not know: a misspelt key must not be silently ignored.
void checkKeys(const std::string& file, const toml::table& table, const std::string& prefix,
               const std::set<std::string>& known) {
  for (const auto& [key, node] : table) {
    if (!known.contains(std::string(key.str()))) {
      std::string expected;
      for (const auto& k : known) expected += (expected.empty() ? "" : ", ") + k;
      fail(file, node, prefix + std::string(key.str()), "unknown key (expected one of: " + expected + ")");
    }
  }
}

RationalRate parseRate(const std::string& file, const toml::node& node) {
  const auto value = node.value<double>();
  if (value) {
    if (std::abs(*value - 59.94) < 1e-6) return {60000, 1001};
    if (*value == 60.0) return {60, 1};
    if (*value == 50.0) return {50, 1};
  }
  fail(file, node, "output.rate", "expected 50, 59.94 or 60, got " + describe(node));
}

void readOutput(const std::string& file, const toml::table& table, OutputConfig& out) {
  checkKeys(file, table, "output.", {"rate", "scan", "field_order", "width", "height", "format"});
  if (const toml::node* n = table.get("rate")) out.fieldRate = parseRate(file, *n);
  if (const toml::node* n = table.get("scan")) {
    const auto s = n->value<std::string>();
    if (s == "interlaced")
      out.scan = ScanMode::Interlaced;
    else if (s == "progressive")
      out.scan = ScanMode::Progressive;
    else
      fail(file, *n, "output.scan", "expected \"interlaced\" or \"progressive\", got " + describe(*n));
  }
  if (const toml::node* n = table.get("field_order")) {
    const auto s = n->value<std::string>();
    if (s == "top_first")
      out.fieldOrder = FieldOrder::TopFirst;
    else if (s == "bottom_first")
      out.fieldOrder = FieldOrder::BottomFirst;
    else
      fail(file, *n, "output.field_order", "expected \"top_first\" or \"bottom_first\", got " + describe(*n));
  }
  auto readSize = [&](const char* key, int& dst, int maxPx) {
    if (const toml::node* n = table.get(key)) {
      const auto v = n->value<std::int64_t>();
      if (!n->is_integer() || !v || *v < 2 || *v > maxPx || *v % 2 != 0) {
        fail(file, *n, std::string("output.") + key,
             "expected an even integer from 2 to " + std::to_string(maxPx) + ", got " + describe(*n));
      }
      dst = static_cast<int>(*v);
    }
  };
  readSize("width", out.widthPx, 8192);
  readSize("height", out.heightPx, 8192);
  if (const toml::node* n = table.get("format")) {
    const auto s = n->value<std::string>();
    if (s == "uyvy422")
      out.format = PixelFormat::Uyvy422;
    else if (s == "rgb8")
      out.format = PixelFormat::Rgb8;
    else if (s == "grey8")
      out.format = PixelFormat::Grey8;
    else
      fail(file, *n, "output.format", "expected \"uyvy422\", \"rgb8\" or \"grey8\", got " + describe(*n));
  }
}

// Applies one --set override ("table.key=value") by parsing the value as TOML.
void applyOverride(toml::table& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  const auto dot = assignment.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot > eq) {
    throw ConfigError("--set " + assignment + ": expected table.key=value");
  }
  const std::string tableName = assignment.substr(0, dot);
  const std::string key = assignment.substr(dot + 1, eq - dot - 1);
  std::string value = assignment.substr(eq + 1);
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    // A bare word is taken as a string, so --set output.scan=progressive works unquoted.
    parsed = toml::parse("v = \"" + value + "\"");
  }
  toml::table* table = root[tableName].as_table();
  if (!table) {
    root.insert(tableName, toml::table{});
    table = root[tableName].as_table();
  }
  table->insert_or_assign(key, *parsed.get("v"));
}

}  // namespace

ServiceConfig loadServiceConfig(const std::string& path, const std::vector<std::string>& overrides) {
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << path << ':' << e.source().begin.line << ": " << e.description();
    throw ConfigError(s.str());
  }
  for (const auto& o : overrides) applyOverride(root, o);

  ServiceConfig config;
  config.sourcePath = path;
  checkKeys(path, root, "", {"output"});
  if (const toml::node* n = root.get("output")) {
    if (!n->is_table()) fail(path, *n, "output", "expected a table");
    readOutput(path, *n->as_table(), config.output);
  }
  if (config.output.scan == ScanMode::Interlaced && config.output.heightPx % 2 != 0) {
    throw ConfigError(path + ": output.height: interlaced output needs an even height");
  }
  return config;
}

}  // namespace fieldcast::app
