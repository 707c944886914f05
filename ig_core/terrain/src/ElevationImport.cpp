// importElevation(): picks the reader by extension, fills nodata holes, settles spacing and origin.
// Hole filling is push-pull (Gortler et al., "The Lumigraph", 1996): valid samples are averaged
// down a pyramid until no hole remains, then holes are filled from the coarser level on the way up.
#include <ig_core/ElevationImport.h>

#include "ElevationReaders.h"

#include <OpenImageIO/imageio.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <type_traits>

namespace fieldcast::core {
namespace detail {
namespace {

template <typename T>
void convertRows(const std::vector<std::byte>& buffer, int w, int h, RawElevation& out, const ImportOptions& options,
                 const std::optional<double>& nodata) {
  // Nodata in the samples' own precision: a Float32 file's "-9999.9" is the float nearest it,
  // which as a double is -9999.900390625, not -9999.9
  const std::optional<double> nodataSample =
      nodata && std::is_same_v<T, float> ? std::optional<double>(static_cast<float>(*nodata)) : nodata;
  for (int y = 0; y < h; ++y) {
    const int row = h - 1 - y;  // image rows run north to south
    for (int x = 0; x < w; ++x) {
      T raw;
      std::memcpy(&raw, buffer.data() + (static_cast<std::size_t>(y) * w + x) * sizeof(T), sizeof(T));
      const auto value = static_cast<double>(raw);
      const std::size_t k = static_cast<std::size_t>(row) * w + x;
      const bool isValid = std::isfinite(value) && !(nodataSample && value == *nodataSample);
      out.valid[k] = isValid ? 1 : 0;
      out.heightsM[k] = isValid ? static_cast<float>(options.verticalOffsetM + options.verticalScaleM * value) : 0.0f;
    }
  }
}

void checkSize(const std::filesystem::path& path, long long w, long long h) {
  if (w < 2 || h < 2 || w > kMaxDatabaseSideVox || h > kMaxDatabaseSideVox) {
    throw ImportError(path.string() + ": grid size " + std::to_string(w) + "x" + std::to_string(h) +
                      " out of range (each side 2.." + std::to_string(kMaxDatabaseSideVox) + ")");
  }
}

}  // namespace

RawElevation readElevationImage(const std::filesystem::path& path, const ImportOptions& options) {
  const std::string name = path.string();
  auto in = OIIO::ImageInput::open(name);
  if (!in) throw ImportError(name + ": cannot read as an image: " + OIIO::geterror());
  const OIIO::ImageSpec spec = in->spec();
  if (spec.nchannels != 1) {
    throw ImportError(name + ": not elevation data: " + std::to_string(spec.nchannels) +
                      " channels (expected one channel of heights; colour images go to --ortho)");
  }
  if (spec.depth > 1) throw ImportError(name + ": not elevation data: a volume image");
  checkSize(path, spec.width, spec.height);
  const OIIO::TypeDesc format = spec.format;
  if (format.basetype == OIIO::TypeDesc::UINT8 || format.basetype == OIIO::TypeDesc::INT8) {
    spdlog::warn("{}: 8-bit heights: only 256 levels of elevation", name);
  }
  GeoTiffInfo geo;
  if (std::string(in->format_name()) == "tiff") {
    checkTiffComplete(path);
    geo = readGeoTiffTags(path);
  }
  const std::optional<double> nodata = options.nodata ? options.nodata : geo.nodata;

  RawElevation out;
  out.width = spec.width;
  out.height = spec.height;
  const auto count = static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height);
  std::vector<std::byte> buffer(count * format.size());
  // A strip that does not decode leaves an error behind even when read_image returns true
  // (OpenImageIO 2.4 fills it with zeros): either way the file cannot be read whole.
  if (!in->read_image(0, 0, 0, 1, format, buffer.data()) || in->has_error()) {
    std::string reason = in->geterror();
    if (const auto end = reason.find('\n'); end != std::string::npos) reason.resize(end);
    throw ImportError(name + ": cannot read the pixels (the file cannot be read whole): " + reason);
  }
  out.heightsM.resize(count);
  out.valid.resize(count);
  switch (format.basetype) {
    case OIIO::TypeDesc::UINT8: convertRows<std::uint8_t>(buffer, out.width, out.height, out, options, nodata); break;
    case OIIO::TypeDesc::INT8: convertRows<std::int8_t>(buffer, out.width, out.height, out, options, nodata); break;
    case OIIO::TypeDesc::UINT16: convertRows<std::uint16_t>(buffer, out.width, out.height, out, options, nodata); break;
    case OIIO::TypeDesc::INT16: convertRows<std::int16_t>(buffer, out.width, out.height, out, options, nodata); break;
    case OIIO::TypeDesc::UINT32: convertRows<std::uint32_t>(buffer, out.width, out.height, out, options, nodata); break;
    case OIIO::TypeDesc::INT32: convertRows<std::int32_t>(buffer, out.width, out.height, out, options, nodata); break;
    case OIIO::TypeDesc::FLOAT: convertRows<float>(buffer, out.width, out.height, out, options, nodata); break;
    case OIIO::TypeDesc::DOUBLE: convertRows<double>(buffer, out.width, out.height, out, options, nodata); break;
    default: throw ImportError(name + ": unsupported sample type " + std::string(format.c_str()) + " for heights");
  }

  if (geo.pixelSizeX && geo.pixelSizeY) {
    const double sx = *geo.pixelSizeX;
    const double sy = *geo.pixelSizeY;
    if (!(sx > 0.0) || !(sy > 0.0) || !std::isfinite(sx) || !std::isfinite(sy)) {
      throw ImportError(name + ": GeoTIFF pixel size " + std::to_string(sx) + " x " + std::to_string(sy) +
                        " is not positive (expected a north-up grid)");
    }
    if (geo.geographic) {
      if (!geo.tieX || !geo.tieY) {
        throw ImportError(name + ": geographic (degree) grid without a tie point: cannot place it");
      }
      GeographicPlacement placement{*geo.tieX, *geo.tieY, sx, sy, "EPSG:4326"};
      if (geo.epsg) {
        placement.crs = "EPSG:" + std::to_string(*geo.epsg);
      } else {
        spdlog::warn("{}: geographic grid without an EPSG code in its GeoKeys; taking WGS 84 (EPSG:4326)", name);
      }
      return reprojectGeographic(out, placement, path);
    }
    if (std::fabs(sx - sy) > 0.01 * sx) {
      throw ImportError(name + ": pixels are " + std::to_string(sx) + " x " + std::to_string(sy) +
                        ", not square; resample to square pixels first (e.g. gdalwarp -tr)");
    }
    out.spacingM = sx;
    if (geo.tieX && geo.tieY) {
      out.originM = glm::dvec2(*geo.tieX + 0.5 * sx, *geo.tieY - (out.height - 0.5) * sy);
      if (geo.epsg) {
        out.crs = "EPSG:" + std::to_string(*geo.epsg);
      } else {
        spdlog::warn(
            "{}: no EPSG code in the GeoKeys (user-defined or absent CRS); the database gets no "
            "georeference",
            name);
      }
    }
  }
  return out;
}

}  // namespace detail

std::size_t fillNodata(std::vector<float>& heightsM, const std::vector<std::uint8_t>& valid, int width, int height) {
  struct Level {
    int w, h;
    std::vector<float> v;
    std::vector<std::uint8_t> ok;
  };
  std::vector<Level> levels;
  levels.push_back({width, height, heightsM, valid});
  std::size_t holes = 0;
  for (const std::uint8_t f : valid) holes += f == 0 ? 1 : 0;
  if (holes == 0) return 0;
  if (holes == valid.size()) throw ImportError("no valid elevation samples (everything is nodata)");
  // Push: average valid samples down until a level has no hole.
  for (;;) {
    const Level& fine = levels.back();
    const bool complete = std::all_of(fine.ok.begin(), fine.ok.end(), [](std::uint8_t f) { return f != 0; });
    if (complete || (fine.w == 1 && fine.h == 1)) break;
    Level coarse{(fine.w + 1) / 2, (fine.h + 1) / 2, {}, {}};
    coarse.v.assign(static_cast<std::size_t>(coarse.w) * coarse.h, 0.0f);
    coarse.ok.assign(coarse.v.size(), 0);
    for (int j = 0; j < coarse.h; ++j) {
      for (int i = 0; i < coarse.w; ++i) {
        double sum = 0.0;
        int n = 0;
        for (int dj = 0; dj < 2; ++dj) {
          for (int di = 0; di < 2; ++di) {
            const int fi = std::min(2 * i + di, fine.w - 1);
            const int fj = std::min(2 * j + dj, fine.h - 1);
            const std::size_t k = static_cast<std::size_t>(fj) * fine.w + fi;
            if (fine.ok[k] != 0) {
              sum += fine.v[k];
              ++n;
            }
          }
        }
        const std::size_t c = static_cast<std::size_t>(j) * coarse.w + i;
        if (n > 0) {
          coarse.v[c] = static_cast<float>(sum / n);
          coarse.ok[c] = 1;
        }
      }
    }
    levels.push_back(std::move(coarse));
  }
  // Pull: fill each level's holes bilinearly from the (complete) level above.
  for (std::size_t l = levels.size() - 1; l-- > 0;) {
    Level& fine = levels[l];
    const Level& coarse = levels[l + 1];
    for (int j = 0; j < fine.h; ++j) {
      for (int i = 0; i < fine.w; ++i) {
        const std::size_t k = static_cast<std::size_t>(j) * fine.w + i;
        if (fine.ok[k] != 0) continue;
        const double ci = std::clamp((i + 0.5) / 2.0 - 0.5, 0.0, coarse.w - 1.0);
        const double cj = std::clamp((j + 0.5) / 2.0 - 0.5, 0.0, coarse.h - 1.0);
        const int i0 = static_cast<int>(ci), j0 = static_cast<int>(cj);
        const int i1 = std::min(i0 + 1, coarse.w - 1), j1 = std::min(j0 + 1, coarse.h - 1);
        const double tx = ci - i0, ty = cj - j0;
        const auto at = [&](int a, int b) {
          return static_cast<double>(coarse.v[static_cast<std::size_t>(b) * coarse.w + a]);
        };
        fine.v[k] = static_cast<float>((at(i0, j0) * (1 - tx) + at(i1, j0) * tx) * (1 - ty) +
                                       (at(i0, j1) * (1 - tx) + at(i1, j1) * tx) * ty);
        fine.ok[k] = 1;
      }
    }
  }
  heightsM = std::move(levels[0].v);
  return holes;
}

ElevationGrid importElevation(const std::filesystem::path& path, const ImportOptions& options) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (!std::filesystem::exists(path)) throw ImportError(path.string() + ": no such file");
  detail::RawElevation raw;
  if (ext == ".asc") {
    raw = detail::readAsciiGrid(path, options);
  } else if (ext == ".raw" || ext == ".bin" || ext == ".r16" || ext == ".r32" || ext == ".f32") {
    raw = detail::readRawGrid(path, options);
  } else {
    raw = detail::readElevationImage(path, options);
  }
  ElevationGrid grid;
  grid.widthVox = raw.width;
  grid.heightVox = raw.height;
  try {
    grid.nodataFilled = fillNodata(raw.heightsM, raw.valid, raw.width, raw.height);
  } catch (const ImportError& e) {
    throw ImportError(path.string() + ": " + e.what());
  }
  grid.heightsM = std::move(raw.heightsM);
  if (options.spacingM > 0.0) {
    grid.spacingM = options.spacingM;
    if (!raw.crs.empty()) {
      spdlog::warn("{}: the given spacing overrides the file's, so its georeference no longer fits: dropped",
                   path.string());
      raw.crs.clear();
    }
  } else if (raw.spacingM) {
    grid.spacingM = *raw.spacingM;
    grid.spacingFromFile = true;
  } else {
    spdlog::warn("{}: the file gives no voxel spacing; using 1 m (set it with --dem-spacing)", path.string());
  }
  if (!(grid.spacingM > 0.0) || !std::isfinite(grid.spacingM)) {
    throw ImportError(path.string() + ": voxel spacing " + std::to_string(grid.spacingM) + " is not positive");
  }
  grid.originM = raw.originM.value_or(glm::dvec2(0.0, 0.0));
  grid.crs = raw.crs;
  const auto [lo, hi] = std::minmax_element(grid.heightsM.begin(), grid.heightsM.end());
  grid.minM = *lo;
  grid.maxM = *hi;
  if (grid.maxM - grid.minM > 65535.0 * 1000.0) {
    throw ImportError(path.string() + ": heights span " + std::to_string(grid.maxM - grid.minM) +
                      " m; not elevation in metres (wrong vertical scale?)");
  }
  return grid;
}

TerrainGrid quantiseElevation(const ElevationGrid& elevation) {
  TerrainGrid grid;
  const HeightQuantisation q = chooseQuantisation(elevation.minM, elevation.maxM);
  grid.geometry.widthVox = elevation.widthVox;
  grid.geometry.heightVox = elevation.heightVox;
  grid.geometry.spacingM = elevation.spacingM;
  grid.geometry.originM = elevation.originM;
  grid.crs = elevation.crs;
  grid.geometry.heightBaseM = q.baseM;
  grid.geometry.heightStepM = q.stepM;
  grid.heightQ.resize(elevation.heightsM.size());
  for (std::size_t k = 0; k < elevation.heightsM.size(); ++k)
    grid.heightQ[k] = quantiseHeight(elevation.heightsM[k], q);
  return grid;
}

}  // namespace fieldcast::core
