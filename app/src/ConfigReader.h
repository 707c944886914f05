#pragma once
// Typed, validated reading of one TOML table. Every getter records the key it read, so finish()
// can reject keys nobody asked for (a misspelt key must never be silently ignored). Errors read
// "file:line: table.key: expected …, got …".
//
// Paths: a relative path written in a file is relative to that file's folder; a relative path
// given on the command line (--set) is relative to the current directory.

#include <toml++/toml.h>

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace fieldcast::app {

/// A configuration error; what() reads "file:line: key: expected …, got …".
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reader over one table of a configuration file.
class ConfigReader {
 public:
  /// `table` may be null (an absent table: every getter answers its default).
  ConfigReader(std::string file, const toml::table* table, std::string prefix);

  /// A number (integer or float) in [min, max].
  double number(const char* key, double fallback, double min, double max);
  /// An integer in [min, max].
  std::int64_t integer(const char* key, std::int64_t fallback, std::int64_t min, std::int64_t max);
  bool boolean(const char* key, bool fallback);
  /// A non-empty string when present.
  std::string string(const char* key, const std::string& fallback);
  /// A path: absolute, or resolved as the header says; "~/" expands to $HOME. Empty stays empty.
  std::filesystem::path path(const char* key, const std::filesystem::path& fallback);
  /// An array of exactly `count` numbers.
  std::vector<double> numbers(const char* key, const std::vector<double>& fallback, std::size_t count);
  /// One of a fixed set of words.
  template <typename E>
  E choice(const char* key, E fallback, std::initializer_list<std::pair<const char*, E>> options) {
    const toml::node* n = take(key);
    if (!n) return fallback;
    const auto s = n->value<std::string>();
    std::string expected;
    for (const auto& [word, value] : options) {
      if (s && *s == word) return value;
      expected += (expected.empty() ? "\"" : ", \"") + std::string(word) + "\"";
    }
    fail(*n, key, "expected one of " + expected);
  }
  /// The raw node of `key` (marked as read), for checks the getters do not cover; null if absent.
  const toml::node* raw(const char* key) { return take(key); }
  /// A nested table (absent: a reader whose getters answer their defaults).
  ConfigReader table(const char* key);
  /// True when the key is present.
  bool has(const char* key) const;
  /// Throws on the first key of this table that no getter asked for.
  void finish() const;

  /// Throws ConfigError located at `node`.
  [[noreturn]] void fail(const toml::node& node, const std::string& key, const std::string& what) const;
  /// Throws ConfigError located at this table.
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;

 private:
  const toml::node* take(const char* key);
  std::string where(const toml::node& node) const;

  std::string mFile;
  const toml::table* mTable;
  std::string mPrefix;
  std::set<std::string> mRead;
};

/// Parses a file and applies "table.key=value" overrides (values parsed as TOML; a bare word is
/// a string). Throws ConfigError naming the file and line of a syntax error.
toml::table parseConfigFile(const std::string& path, const std::vector<std::string>& overrides);

}  // namespace fieldcast::app
