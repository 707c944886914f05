// Draping an orthophoto over the voxel grid: each voxel averages n×n bilinear samples of the photo
// across its footprint (n = photo pixels per voxel, 1..8), so a photo finer than the grid is
// box-filtered rather than aliased.
#include <ig_core/TerrainColour.h>

#include "ElevationReaders.h"
#include "Parallel.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fieldcast::core {

std::vector<std::uint32_t> drapeOrthophoto(const std::filesystem::path& image, const TerrainGeometry& geometry,
                                           const OrthophotoPlacement& placement, ColourOutput output,
                                           std::uint32_t outside, int threads) {
  const std::string name = image.string();
  auto in = OIIO::ImageInput::open(name);
  if (!in) throw std::runtime_error(name + ": cannot read the orthophoto: " + OIIO::geterror());
  const OIIO::ImageSpec spec = in->spec();
  const int channels = spec.nchannels;
  if (channels < 1 || channels > 4 || spec.width < 1 || spec.height < 1) {
    throw std::runtime_error(name + ": orthophoto with " + std::to_string(channels) +
                             " channels (expected grey, grey+alpha, RGB or RGBA)");
  }
  const auto pixels = static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height);
  if (pixels > (std::size_t{1} << 32)) throw std::runtime_error(name + ": orthophoto larger than 2^32 pixels");
  std::vector<std::uint8_t> photo(pixels * static_cast<std::size_t>(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, photo.data())) {
    throw std::runtime_error(name + ": cannot read the orthophoto's pixels: " + in->geterror());
  }

  // World position of the photo's top-left corner and its pixel size.
  const double dx = geometry.spacingM;
  double left = geometry.originM.x - 0.5 * dx;
  double top = geometry.originM.y + (geometry.heightVox - 0.5) * dx;
  double sx = geometry.widthVox * dx / spec.width;
  double sy = geometry.heightVox * dx / spec.height;
  bool placed = false;
  if (placement.fromFile && std::string(in->format_name()) == "tiff") {
    const detail::GeoTiffInfo geo = detail::readGeoTiffTags(image);
    if (geo.pixelSizeX && geo.pixelSizeY && geo.tieX && geo.tieY && !geo.geographic) {
      left = *geo.tieX;
      top = *geo.tieY;
      sx = *geo.pixelSizeX;
      sy = *geo.pixelSizeY;
      placed = true;
    }
  }
  if (!placed && !placement.stretchToGrid) {
    left = placement.topLeftXM;
    top = placement.topLeftYM;
    sx = placement.pixelSizeXM;
    sy = placement.pixelSizeYM;
  }
  if (!(sx > 0.0) || !(sy > 0.0)) throw std::runtime_error(name + ": orthophoto pixel size must be positive");
  const int n = std::clamp(static_cast<int>(std::lround(dx / std::min(sx, sy))), 1, 8);

  const int w = geometry.widthVox;
  const int h = geometry.heightVox;
  std::vector<std::uint32_t> colours(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  detail::parallelFor(static_cast<std::size_t>(h), threads, 16, [&](std::size_t begin, std::size_t end) {
    for (auto j = static_cast<int>(begin); j < static_cast<int>(end); ++j) {
      for (int i = 0; i < w; ++i) {
        double sum[3] = {0.0, 0.0, 0.0};
        int count = 0;
        for (int b = 0; b < n; ++b) {
          for (int a = 0; a < n; ++a) {
            const double x = geometry.originM.x + (i + (a + 0.5) / n - 0.5) * dx;
            const double y = geometry.originM.y + (j + (b + 0.5) / n - 0.5) * dx;
            const double u = (x - left) / sx - 0.5;  // continuous pixel index (centres at integers)
            const double v = (top - y) / sy - 0.5;
            if (u < -0.5 || v < -0.5 || u > spec.width - 0.5 || v > spec.height - 0.5) continue;
            const double uc = std::clamp(u, 0.0, spec.width - 1.0);
            const double vc = std::clamp(v, 0.0, spec.height - 1.0);
            const int u0 = static_cast<int>(uc), v0 = static_cast<int>(vc);
            const int u1 = std::min(u0 + 1, spec.width - 1), v1 = std::min(v0 + 1, spec.height - 1);
            const double tu = uc - u0, tv = vc - v0;
            for (int c = 0; c < 3; ++c) {
              const int src = channels >= 3 ? c : 0;  // grey (and grey+alpha) feeds all three
              const auto at = [&](int pu, int pv) {
                return static_cast<double>(
                    photo[(static_cast<std::size_t>(pv) * spec.width + pu) * static_cast<std::size_t>(channels) + src]);
              };
              sum[c] +=
                  (at(u0, v0) * (1 - tu) + at(u1, v0) * tu) * (1 - tv) + (at(u0, v1) * (1 - tu) + at(u1, v1) * tu) * tv;
            }
            ++count;
          }
        }
        const std::size_t k = static_cast<std::size_t>(j) * w + i;
        if (count == 0) {
          colours[k] = outside;
          continue;
        }
        auto r = static_cast<std::uint32_t>(std::lround(sum[0] / count));
        auto g = static_cast<std::uint32_t>(std::lround(sum[1] / count));
        auto b = static_cast<std::uint32_t>(std::lround(sum[2] / count));
        if (output == ColourOutput::Grey) r = g = b = (77u * r + 150u * g + 29u * b + 128u) >> 8;
        colours[k] = packRgba(r, g, b);
      }
    }
  });
  return colours;
}

}  // namespace fieldcast::core
