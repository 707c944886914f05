// Raw little-endian grids (int16, uint16 or float32 samples, row-major) with a small TOML sidecar
// beside them, "<file>.toml" (dem.raw.toml) or "<stem>.toml" (dem.toml):
//   width = 1024            height = 1024         type = "int16"   (int16 | uint16 | float32)
//   spacing_m = 2.0         origin_x_m = 0.0      origin_y_m = 0.0 (centre of the south-west sample)
//   nodata = -32768         row_order = "north_first" (or "south_first")
//   scale = 1.0             offset_m = 0.0        (metres = offset_m + scale * sample)
#include "ElevationReaders.h"

#include <toml++/toml.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

namespace fieldcast::core::detail {
namespace {

struct RawLayout {
  int width = 0;
  int height = 0;
  std::string type = "int16";
  bool northFirst = true;
  double scale = 1.0;
  double offsetM = 0.0;
  std::optional<double> nodata;
  std::optional<double> spacingM;
  std::optional<glm::dvec2> originM;
};

std::size_t sampleBytes(const std::string& type) {
  if (type == "int16" || type == "uint16") return 2;
  if (type == "float32") return 4;
  return 0;
}

RawLayout readSidecar(const std::filesystem::path& sidecar) {
  const std::string name = sidecar.string();
  toml::table table;
  try {
    table = toml::parse_file(name);
  } catch (const toml::parse_error& e) {
    throw ImportError(name + ":" + std::to_string(e.source().begin.line) + ": " + std::string(e.description()));
  }
  RawLayout layout;
  const auto integer = [&](const char* key) {
    const std::optional<std::int64_t> v = table[key].value<std::int64_t>();
    if (!v || *v < 2 || *v > kMaxDatabaseSideVox) {
      throw ImportError(name + ": " + key + ": expected an integer 2.." + std::to_string(kMaxDatabaseSideVox));
    }
    return static_cast<int>(*v);
  };
  const auto number = [&](const char* key) -> std::optional<double> {
    if (!table.contains(key)) return std::nullopt;
    const std::optional<double> v = table[key].value<double>();
    if (!v || !std::isfinite(*v)) throw ImportError(name + ": " + key + ": expected a number");
    return v;
  };
  layout.width = integer("width");
  layout.height = integer("height");
  layout.type = table["type"].value_or(std::string("int16"));
  if (sampleBytes(layout.type) == 0) {
    throw ImportError(name + ": type: expected \"int16\", \"uint16\" or \"float32\", got \"" + layout.type + "\"");
  }
  const std::string order = table["row_order"].value_or(std::string("north_first"));
  if (order != "north_first" && order != "south_first") {
    throw ImportError(name + ": row_order: expected \"north_first\" or \"south_first\", got \"" + order + "\"");
  }
  layout.northFirst = order == "north_first";
  layout.spacingM = number("spacing_m");
  if (layout.spacingM && !(*layout.spacingM > 0.0)) throw ImportError(name + ": spacing_m: expected a positive number");
  const std::optional<double> ox = number("origin_x_m");
  const std::optional<double> oy = number("origin_y_m");
  if (ox || oy) layout.originM = glm::dvec2(ox.value_or(0.0), oy.value_or(0.0));
  layout.nodata = number("nodata");
  layout.scale = number("scale").value_or(1.0);
  layout.offsetM = number("offset_m").value_or(0.0);
  return layout;
}

template <typename T>
float sampleAt(const std::vector<char>& bytes, std::size_t k) {
  T v;
  std::memcpy(&v, bytes.data() + k * sizeof(T), sizeof(T));
  return static_cast<float>(v);
}

}  // namespace

RawElevation readRawGrid(const std::filesystem::path& path, const ImportOptions& options) {
  const std::string name = path.string();
  RawLayout layout;
  std::filesystem::path sidecar = path;
  sidecar += ".toml";
  if (!std::filesystem::exists(sidecar)) sidecar = std::filesystem::path(path).replace_extension(".toml");
  if (std::filesystem::exists(sidecar)) {
    layout = readSidecar(sidecar);
  } else if (options.rawWidth > 0 && options.rawHeight > 0) {
    layout.width = options.rawWidth;
    layout.height = options.rawHeight;
    layout.type = options.rawType;
    if (sampleBytes(layout.type) == 0) throw ImportError(name + ": raw type must be int16, uint16 or float32");
    if (layout.width < 2 || layout.height < 2 || layout.width > kMaxDatabaseSideVox ||
        layout.height > kMaxDatabaseSideVox) {
      throw ImportError(name + ": raw size out of range");
    }
  } else {
    throw ImportError(name + ": raw grid without a sidecar (" + path.filename().string() +
                      ".toml with width, height, type) and without --raw-size");
  }
  if (!layout.nodata) layout.nodata = options.nodata;
  const std::size_t count = static_cast<std::size_t>(layout.width) * static_cast<std::size_t>(layout.height);
  const std::size_t expected = count * sampleBytes(layout.type);
  const std::uintmax_t actual = std::filesystem::file_size(path);
  if (actual != expected) {
    throw ImportError(name + ": expected " + std::to_string(expected) + " bytes (" + std::to_string(layout.width) +
                      " x " + std::to_string(layout.height) + " " + layout.type + "), the file has " +
                      std::to_string(actual));
  }
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes(expected);
  if (!in.read(bytes.data(), static_cast<std::streamsize>(expected))) throw ImportError(name + ": read failed");

  RawElevation out;
  out.width = layout.width;
  out.height = layout.height;
  out.spacingM = layout.spacingM;
  out.originM = layout.originM;
  out.heightsM.resize(count);
  out.valid.resize(count);
  for (std::size_t k = 0; k < count; ++k) {
    float v = 0.0f;
    if (layout.type == "int16") {
      v = sampleAt<std::int16_t>(bytes, k);
    } else if (layout.type == "uint16") {
      v = sampleAt<std::uint16_t>(bytes, k);
    } else {
      v = sampleAt<float>(bytes, k);
    }
    const std::size_t x = k % static_cast<std::size_t>(out.width);
    const std::size_t y = k / static_cast<std::size_t>(out.width);
    const std::size_t row = layout.northFirst ? static_cast<std::size_t>(out.height) - 1 - y : y;
    const std::size_t i = row * static_cast<std::size_t>(out.width) + x;
    const bool isValid = std::isfinite(v) && !(layout.nodata && static_cast<double>(v) == *layout.nodata);
    out.valid[i] = isValid ? 1 : 0;
    out.heightsM[i] = isValid ? static_cast<float>(layout.offsetM + layout.scale * v) : 0.0f;
  }
  return out;
}

}  // namespace fieldcast::core::detail
