#pragma once
// CLI11 validators for the tools' numeric options. CLI::Range alone lets "nan" through (every
// comparison with NaN is false), wraps "-1" into a huge unsigned seed and says "not in range"
// without the range or the unit; these say what was expected: "expected a finite number from
// 0.01 to 100000 m, got '-1'".

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdint>
#include <functional>
#include <sstream>
#include <string>

namespace fieldcast::tools {

/// `v` as the shortest text a person reads back ("0.01", "100000", "1e-06").
inline std::string formatNumber(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// A number that `accept` takes; otherwise "expected <expected>, got '<text>'".
inline CLI::Validator numberCheck(std::function<bool(double)> accept, const std::string& expected,
                                  const std::string& desc) {
  return CLI::Validator(
      [accept = std::move(accept), expected](std::string& text) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v) || !accept(v)) return "expected " + expected + ", got '" + text + "'";
        return {};
      },
      desc);
}

/// A finite number in [min, max]. CLI::Range alone lets "nan" through (every comparison with NaN
/// is false) and says nothing of units; the message names what was expected with its unit.
inline CLI::Validator finiteRange(double min, double max, const std::string& unit) {
  return numberCheck(
      [=](double v) { return v >= min && v <= max; },
      "a finite number from " + formatNumber(min) + " to " + formatNumber(max) + (unit.empty() ? "" : " " + unit),
      "[" + formatNumber(min) + ".." + formatNumber(max) + "]");
}

/// Any finite number (e.g. a nodata value: -32768, -9999, -3.4e38 are all in use).
inline CLI::Validator finiteNumber() {
  return numberCheck([](double v) { return std::isfinite(v); }, "a finite number", "NUMBER");
}

/// An integer in [min, max], the message saying so (CLI11's own says "not in range").
inline CLI::Validator intRange(long long min, long long max, const std::string& unit) {
  const std::string expected =
      "an integer from " + std::to_string(min) + " to " + std::to_string(max) + (unit.empty() ? "" : " " + unit);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        long long v = 0;
        if (!CLI::detail::lexical_cast(text, v) || v < min || v > max) {
          return "expected " + expected + ", got '" + text + "'";
        }
        return {};
      },
      "[" + std::to_string(min) + ".." + std::to_string(max) + "]");
}

/// A seed: a whole number 0 .. 2^64-1 (CLI11 would wrap "-1" to 2^64-1).
inline CLI::Validator seedNumber() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::uint64_t v = 0;
        if (text.empty() || text.front() == '-' || !CLI::detail::lexical_cast(text, v)) {
          return "expected a whole number from 0 to 18446744073709551615, got '" + text + "'";
        }
        return {};
      },
      "SEED");
}

}  // namespace fieldcast::tools
