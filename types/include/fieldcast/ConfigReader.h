#pragma once
// Strict, typed reading of TOML configuration: the service's file, flight files, stick profiles.
// Every getter records the key it read, so finish() can reject keys nobody asked for (a misspelt
// key must never be silently ignored). Errors read "file:line: table.key: expected …, got …".
// Each module reads its own section with a function of its own (readRenderConfig, …) through
// this one reader; the TOML library stays behind it.
//
// Paths: a relative path written in a file is relative to that file's folder; a relative path
// given on the command line (--set) is relative to the current directory.

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fieldcast {

/// A configuration error; what() reads "file:line: key: expected …, got …".
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ConfigReader;

/// A parsed configuration file (or text). Owns the document its readers look into.
class ConfigDocument {
 public:
  /// Parses a file and applies "table.key=value" overrides (values parsed as TOML; a bare word
  /// is a string). Throws ConfigError naming the file and line of a syntax error.
  static ConfigDocument parseFile(const std::filesystem::path& path, const std::vector<std::string>& overrides = {});
  /// Parses TOML text; `origin` names it in errors (and relative paths are relative to its folder).
  static ConfigDocument parseText(std::string_view text, const std::string& origin);

  /// A reader over the top-level table.
  ConfigReader root() const;

 private:
  struct Data;
  explicit ConfigDocument(std::shared_ptr<const Data> data) : mData(std::move(data)) {}
  std::shared_ptr<const Data> mData;
};

/// Reader over one table of a configuration document. Start-up only (allocates, throws).
class ConfigReader {
 public:
  /// A number (integer or float), finite, in [min, max].
  double number(const char* key, double fallback, double min, double max);
  /// An integer in [min, max].
  std::int64_t integer(const char* key, std::int64_t fallback, std::int64_t min, std::int64_t max);
  /// An integer in [min, max] when present.
  std::optional<std::int64_t> optionalInteger(const char* key, std::int64_t min, std::int64_t max);
  bool boolean(const char* key, bool fallback);
  /// A string when present.
  std::string string(const char* key, const std::string& fallback);
  /// A non-empty string when present.
  std::string nonEmptyString(const char* key, const std::string& fallback);
  /// A path: absolute, or resolved as the header says; "~/" expands to $HOME. Empty stays empty.
  std::filesystem::path path(const char* key, const std::filesystem::path& fallback);
  /// An array of exactly `count` finite numbers.
  std::vector<double> numbers(const char* key, const std::vector<double>& fallback, std::size_t count);
  /// An array of integers in [min, max], at most `maxCount` of them; absent: empty.
  std::vector<std::int64_t> integers(const char* key, std::int64_t min, std::int64_t max, std::size_t maxCount);
  /// A string or an array of strings; absent: nullopt.
  std::optional<std::vector<std::string>> strings(const char* key);
  /// One of a fixed set of words.
  template <typename E>
  E choice(const char* key, E fallback, std::initializer_list<std::pair<const char*, E>> options) {
    const std::optional<std::string> word = choiceWord(key);
    if (!word) return fallback;
    std::string expected;
    for (const auto& [name, value] : options) {
      if (*word == name) return value;
      expected += (expected.empty() ? "\"" : ", \"") + std::string(name) + "\"";
    }
    fail(key, "expected one of " + expected);
  }
  /// A nested table (absent: a reader whose getters answer their defaults).
  ConfigReader table(const char* key);
  /// An array of tables ([[key]]), each with prefix "key[n]." (n from 1); absent: empty.
  std::vector<ConfigReader> tables(const char* key);
  /// True when the key is present.
  bool has(const char* key) const;
  /// Throws on the first key of this table that no getter asked for.
  void finish() const;

  /// Throws ConfigError located at `key` (its line when present, else this table's) with the
  /// key's value appended when present: "file:line: table.key: <what>, got <value>".
  [[noreturn]] void fail(const char* key, const std::string& what) const;

  /// The file this table was read from.
  const std::string& file() const noexcept { return mFile; }

 private:
  friend class ConfigDocument;
  // `table` points at a toml::table of the document `owner` keeps alive; null: an absent table.
  ConfigReader(std::shared_ptr<const void> owner, std::string file, const void* table, std::string prefix);
  const void* take(const char* key);
  std::optional<std::string> choiceWord(const char* key);
  [[noreturn]] void failAt(const void* node, const std::string& key, const std::string& what) const;

  std::shared_ptr<const void> mOwner;
  std::string mFile;
  const void* mTable;  // const toml::table*: the TOML library stays out of this header
  std::string mPrefix;
  std::set<std::string> mRead;
};

}  // namespace fieldcast
