// Raw little-endian grids (int16, uint16 or float32 samples, row-major) with a small TOML sidecar
// beside them, "<file>.toml" (dem.raw.toml) or "<stem>.toml" (dem.toml):
//   width = 1024            height = 1024         type = "int16"   (int16 | uint16 | float32)
//   spacing_m = 2.0         origin_x_m = 0.0      origin_y_m = 0.0 (centre of the south-west sample)
//   nodata = -32768         row_order = "north_first" (or "south_first")
//   scale = 1.0             offset_m = 0.0        (metres = offset_m + scale * sample)
#include "ElevationReaders.h"

#include <fieldcast/ConfigReader.h>

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

RawLayout readSidecarTable(ConfigReader& t) {
  RawLayout layout;
  for (const char* key : {"width", "height"}) {
    if (!t.has(key)) t.fail(key, "expected an integer 2.." + std::to_string(kMaxDatabaseSideVox));
  }
  layout.width = static_cast<int>(t.integer("width", 0, 2, kMaxDatabaseSideVox));
  layout.height = static_cast<int>(t.integer("height", 0, 2, kMaxDatabaseSideVox));
  layout.type = t.choice(
      "type", std::string("int16"),
      {{"int16", std::string("int16")}, {"uint16", std::string("uint16")}, {"float32", std::string("float32")}});
  layout.northFirst = t.choice("row_order", true, {{"north_first", true}, {"south_first", false}});
  constexpr double kAny = 1e300;  // any finite number
  if (t.has("spacing_m")) layout.spacingM = t.number("spacing_m", 0.0, 1e-300, kAny);
  if (t.has("origin_x_m") || t.has("origin_y_m")) {
    layout.originM = glm::dvec2(t.number("origin_x_m", 0.0, -kAny, kAny), t.number("origin_y_m", 0.0, -kAny, kAny));
  }
  if (t.has("nodata")) layout.nodata = t.number("nodata", 0.0, -kAny, kAny);
  layout.scale = t.number("scale", 1.0, -kAny, kAny);
  layout.offsetM = t.number("offset_m", 0.0, -kAny, kAny);
  t.finish();
  return layout;
}

RawLayout readSidecar(const std::filesystem::path& sidecar) {
  try {
    ConfigReader t = ConfigDocument::parseFile(sidecar).root();
    return readSidecarTable(t);
  } catch (const ConfigError& e) {
    throw ImportError(e.what());
  }
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
    // In the samples' precision (float): a float32 file's nodata -9999.9 is the float nearest it
    const bool isValid = std::isfinite(v) && !(layout.nodata && v == static_cast<float>(*layout.nodata));
    out.valid[i] = isValid ? 1 : 0;
    out.heightsM[i] = isValid ? static_cast<float>(layout.offsetM + layout.scale * v) : 0.0f;
  }
  return out;
}

}  // namespace fieldcast::core::detail
