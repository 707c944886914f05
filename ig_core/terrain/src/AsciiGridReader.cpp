// ESRI ASCII grid (.asc): a header of "key value" lines (ncols, nrows, xllcorner|xllcenter,
// yllcorner|yllcenter, cellsize, optional NODATA_value), then nrows rows of ncols numbers, the
// northern row first.
#include "ElevationReaders.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <string>

namespace fieldcast::core::detail {
namespace {

// Walks the text token by token, counting lines for error messages.
class Tokens {
 public:
  explicit Tokens(const std::string& text) : mText(text) {}
  bool next(std::string_view& token) {
    while (mPos < mText.size() && std::isspace(static_cast<unsigned char>(mText[mPos])) != 0) {
      if (mText[mPos] == '\n') ++mLine;
      ++mPos;
    }
    if (mPos >= mText.size()) return false;
    const std::size_t start = mPos;
    while (mPos < mText.size() && std::isspace(static_cast<unsigned char>(mText[mPos])) == 0) ++mPos;
    token = std::string_view(mText).substr(start, mPos - start);
    return true;
  }
  void pushBack(std::string_view token) { mPos -= token.size(); }
  int line() const { return mLine; }

 private:
  const std::string& mText;
  std::size_t mPos = 0;
  int mLine = 1;
};

bool parseNumber(std::string_view token, double& value) {
  const char* first = token.data();
  if (!token.empty() && token.front() == '+') ++first;
  const auto [end, ec] = std::from_chars(first, token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size();
}

}  // namespace

RawElevation readAsciiGrid(const std::filesystem::path& path, const ImportOptions& options) {
  const std::string name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ImportError(name + ": cannot open");
  std::string text(static_cast<std::size_t>(std::filesystem::file_size(path)), '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(text.size()))) throw ImportError(name + ": read failed");
  Tokens tokens(text);
  const auto where = [&] { return name + ":" + std::to_string(tokens.line()) + ": "; };

  std::map<std::string, double> header;
  std::string_view token;
  while (tokens.next(token)) {
    if (std::isalpha(static_cast<unsigned char>(token.front())) == 0) {
      tokens.pushBack(token);
      break;
    }
    std::string key(token);
    std::transform(key.begin(), key.end(), key.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    static const char* const kKeys[] = {"ncols",     "nrows",    "xllcorner", "yllcorner", "xllcenter",
                                        "yllcenter", "cellsize", "dx",        "dy",        "nodata_value"};
    if (std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys)) {
      throw ImportError(where() + "unknown header key '" + key +
                        "' (expected ncols, nrows, xllcorner/xllcenter, yllcorner/yllcenter, cellsize, NODATA_value)");
    }
    std::string_view valueToken;
    double value = 0.0;
    if (!tokens.next(valueToken) || !parseNumber(valueToken, value)) {
      throw ImportError(where() + key + ": expected a number, got '" + std::string(valueToken) + "'");
    }
    header[key] = value;
  }
  for (const char* required : {"ncols", "nrows"}) {
    if (!header.contains(required))
      throw ImportError(name + ": not an ESRI ASCII grid: no '" + required + "' in the header");
  }
  if (!header.contains("cellsize") && !header.contains("dx")) throw ImportError(name + ": header has no 'cellsize'");
  const double cols = header["ncols"];
  const double rows = header["nrows"];
  if (cols != std::floor(cols) || rows != std::floor(rows) || cols < 2 || rows < 2 || cols > kMaxDatabaseSideVox ||
      rows > kMaxDatabaseSideVox) {
    throw ImportError(name + ": ncols/nrows " + std::to_string(cols) + " x " + std::to_string(rows) +
                      " out of range (whole numbers 2.." + std::to_string(kMaxDatabaseSideVox) + ")");
  }
  const double cell = header.contains("cellsize") ? header["cellsize"] : header["dx"];
  if (header.contains("dy") && std::fabs(header["dy"] - cell) > 0.01 * cell) {
    throw ImportError(name + ": dx and dy differ; resample to square cells first");
  }
  if (!(cell > 0.0) || !std::isfinite(cell)) throw ImportError(name + ": cellsize must be positive");

  RawElevation out;
  out.width = static_cast<int>(cols);
  out.height = static_cast<int>(rows);
  out.spacingM = cell;
  const double xCentre = header.contains("xllcenter") ? header["xllcenter"] : header["xllcorner"] + 0.5 * cell;
  const double yCentre = header.contains("yllcenter") ? header["yllcenter"] : header["yllcorner"] + 0.5 * cell;
  out.originM = glm::dvec2(xCentre, yCentre);
  const std::optional<double> nodata =
      header.contains("nodata_value") ? std::optional<double>(header["nodata_value"]) : options.nodata;
  const std::size_t count = static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height);
  // Each value takes a digit and a separator at least: a header asking for more than the file can
  // hold is refused before it sizes the arrays (a 60-byte file could ask for hundreds of GB)
  if (count > text.size() / 2 + 1) {
    throw ImportError(name + ": expected " + std::to_string(out.width) + " x " + std::to_string(out.height) + " = " +
                      std::to_string(count) + " values, but the file has only " + std::to_string(text.size()) +
                      " bytes (truncated?)");
  }
  out.heightsM.resize(count);
  out.valid.resize(count);
  for (std::size_t k = 0; k < count; ++k) {
    double value = 0.0;
    if (!tokens.next(token)) {
      throw ImportError(name + ": expected " + std::to_string(out.width) + " x " + std::to_string(out.height) + " = " +
                        std::to_string(count) + " values, found " + std::to_string(k) + " (truncated?)");
    }
    if (!parseNumber(token, value)) {
      throw ImportError(where() + "expected a number, got '" + std::string(token.substr(0, 40)) + "'");
    }
    const std::size_t x = k % static_cast<std::size_t>(out.width);
    const std::size_t row = static_cast<std::size_t>(out.height) - 1 - k / static_cast<std::size_t>(out.width);
    const std::size_t i = row * static_cast<std::size_t>(out.width) + x;  // first row is the northern one
    const bool isValid = std::isfinite(value) && !(nodata && value == *nodata);
    out.valid[i] = isValid ? 1 : 0;
    out.heightsM[i] = isValid ? static_cast<float>(options.verticalOffsetM + options.verticalScaleM * value) : 0.0f;
  }
  if (tokens.next(token)) {
    throw ImportError(where() + "more values than ncols x nrows = " + std::to_string(count));
  }
  return out;
}

}  // namespace fieldcast::core::detail
