// Reconstruction from projection: the visual hull of three orthographic silhouettes (Cohen-Or et
// al. build their textured voxel models this way from photographs, DESIGN.md §2), coloured from
// the photograph facing each surface voxel.
#include <ig_core/Sculpt.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fieldcast::core {
namespace {

constexpr double kMinHeightM = 0.5, kMaxHeightM = 128.0;
constexpr int kMaxSideVoxels = 256;

int channel(std::uint32_t rgba, int c) { return static_cast<int>((rgba >> (8 * c)) & 0xFFu); }

// A silhouette cropped to its object, with a summed-area table of `inside` for coverage queries
class View {
 public:
  View(const Silhouette& s, const char* name) : mS(s) {
    int x0 = s.width, y0 = s.height, x1 = -1, y1 = -1;
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x)
        if (s.inside[static_cast<std::size_t>(y) * static_cast<std::size_t>(s.width) + static_cast<std::size_t>(x)]) {
          x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
    if (x1 < 0) throw std::invalid_argument(std::string("the ") + name + " view shows no object");
    mX0 = x0, mY0 = y0, mW = x1 - x0 + 1, mH = y1 - y0 + 1;
    mSum.assign(static_cast<std::size_t>(mW + 1) * static_cast<std::size_t>(mH + 1), 0);
    for (int y = 0; y < mH; ++y)
      for (int x = 0; x < mW; ++x)
        mSum[at(x + 1, y + 1)] = mSum[at(x, y + 1)] + mSum[at(x + 1, y)] - mSum[at(x, y)] + isInside(x, y);
  }
  int width() const { return mW; }
  int height() const { return mH; }

  // The pixels of the box's fraction [u0, u1) × [v0, v1), at least one pixel
  struct Rect {
    int x0, y0, x1, y1;
  };
  Rect rect(double u0, double u1, double v0, double v1) const {
    const auto edge = [](double f, int n) { return std::clamp(static_cast<int>(std::lround(f * n)), 0, n); };
    Rect r{edge(u0, mW), edge(v0, mH), edge(u1, mW), edge(v1, mH)};
    if (r.x1 <= r.x0) r.x1 = std::min(r.x0 + 1, mW), r.x0 = r.x1 - 1;
    if (r.y1 <= r.y0) r.y1 = std::min(r.y0 + 1, mH), r.y0 = r.y1 - 1;
    return r;
  }
  // Whether at least half of the rectangle is the object
  bool covers(const Rect& r) const {
    const int inside = mSum[at(r.x1, r.y1)] - mSum[at(r.x0, r.y1)] - mSum[at(r.x1, r.y0)] + mSum[at(r.x0, r.y0)];
    return 2 * inside >= (r.x1 - r.x0) * (r.y1 - r.y0);
  }
  // The mean colour of the object's pixels in the rectangle
  std::uint32_t colour(const Rect& r) const {
    std::array<long, 3> sum{};
    long n = 0;
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) {
        if (!isInside(x, y)) continue;
        const std::uint32_t c = mS.rgba[pixel(x, y)];
        for (int k = 0; k < 3; ++k) sum[static_cast<std::size_t>(k)] += channel(c, k);
        ++n;
      }
    std::uint32_t out = 0xFF000000u;
    for (int k = 0; k < 3; ++k)
      out |= static_cast<std::uint32_t>((sum[static_cast<std::size_t>(k)] + n / 2) / std::max(n, 1L)) << (8 * k);
    return out;
  }

 private:
  std::size_t at(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(mW + 1) + static_cast<std::size_t>(x);
  }
  std::size_t pixel(int x, int y) const {
    return static_cast<std::size_t>(y + mY0) * static_cast<std::size_t>(mS.width) + static_cast<std::size_t>(x + mX0);
  }
  int isInside(int x, int y) const { return mS.inside[pixel(x, y)] != 0 ? 1 : 0; }

  const Silhouette& mS;
  int mX0 = 0, mY0 = 0, mW = 0, mH = 0;
  std::vector<int> mSum;
};

int voxelsFor(double metres, const char* what) {
  const int n = std::max(1, static_cast<int>(std::lround(metres / kSolidVoxelM)));
  if (n > kMaxSideVoxels) {
    throw std::invalid_argument(std::string("the object's ") + what + " is " + std::to_string(metres) +
                                " m: more than " + std::to_string(kMaxSideVoxels) + " voxels of " +
                                std::to_string(kSolidVoxelM) + " m");
  }
  return n;
}

}  // namespace

Silhouette keySilhouette(int width, int height, std::vector<std::uint32_t> rgba, const BackgroundKey& key) {
  if (width < 1 || height < 1 || rgba.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {
    throw std::invalid_argument("a silhouette's pixels do not match its size");
  }
  Silhouette s{width, height, std::move(rgba), {}};
  s.inside.resize(s.rgba.size());
  for (std::size_t i = 0; i < s.rgba.size(); ++i) {
    const std::uint32_t c = s.rgba[i];
    bool background = channel(c, 3) < 128;
    if (key.keyRgb) {
      int distance = 0;
      for (int k = 0; k < 3; ++k) distance = std::max(distance, std::abs(channel(c, k) - channel(*key.keyRgb, k)));
      background = background || distance <= key.tolerance;
    }
    s.inside[i] = background ? 0 : 1;
  }
  return s;
}

Silhouette readSilhouette(const std::filesystem::path& path, const BackgroundKey& key) {
  const std::string name = path.string();
  auto in = OIIO::ImageInput::open(name);
  if (!in) throw std::runtime_error(name + ": cannot read the photograph: " + OIIO::geterror());
  const OIIO::ImageSpec spec = in->spec();
  const int channels = spec.nchannels;
  if (channels < 1 || channels > 4 || spec.width < 1 || spec.height < 1 || spec.width > 16384 || spec.height > 16384) {
    throw std::runtime_error(name + ": a photograph of " + std::to_string(spec.width) + " × " +
                             std::to_string(spec.height) + " pixels, " + std::to_string(channels) +
                             " channels (expected grey, RGB or RGBA, ≤ 16384 a side)");
  }
  const bool hasAlpha = channels == 2 || channels == 4;
  if (!hasAlpha && !key.keyRgb) {
    throw std::runtime_error(name + ": no alpha channel to separate the object; give the background's key colour");
  }
  const auto pixels = static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height);
  std::vector<std::uint8_t> raw(pixels * static_cast<std::size_t>(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, raw.data())) {
    throw std::runtime_error(name + ": cannot read the photograph's pixels: " + in->geterror());
  }
  std::vector<std::uint32_t> rgba(pixels);
  for (std::size_t i = 0; i < pixels; ++i) {
    const std::uint8_t* p = raw.data() + i * static_cast<std::size_t>(channels);
    const std::uint32_t r = p[0], g = channels >= 3 ? p[1] : p[0], b = channels >= 3 ? p[2] : p[0];
    const std::uint32_t a = hasAlpha ? p[channels - 1] : 255u;
    rgba[i] = r | (g << 8) | (b << 16) | (a << 24);
  }
  Silhouette s = keySilhouette(spec.width, spec.height, std::move(rgba), key);
  if (std::none_of(s.inside.begin(), s.inside.end(), [](std::uint8_t v) { return v != 0; })) {
    throw std::runtime_error(name + ": the photograph shows no object (all of it is background)");
  }
  return s;
}

SculptResult sculptFromSilhouettes(const SculptViews& views, double heightM) {
  if (!(heightM >= kMinHeightM && heightM <= kMaxHeightM)) {
    throw std::invalid_argument("an object's height of " + std::to_string(heightM) + " m (0.5 … 128 m)");
  }
  const View side(views.side, "side"), front(views.front, "front"), top(views.top, "top");
  SculptResult r;
  r.heightM = heightM;
  r.depthM = side.width() * heightM / side.height();
  r.widthM = front.width() * heightM / front.height();
  const double topAspect = static_cast<double>(top.width()) / top.height();
  r.topAspectError = std::abs(topAspect / (r.widthM / r.depthM) - 1.0);
  if (r.topAspectError > kMaxTopAspectError) {
    throw std::invalid_argument("the top view's object is " + std::to_string(top.width()) + " × " +
                                std::to_string(top.height()) + " px, but the side and front make it " +
                                std::to_string(r.widthM) + " m wide and " + std::to_string(r.depthM) +
                                " m deep: are the three of one object, the top with its front up?");
  }
  r.solid = emptySolid(voxelsFor(r.widthM, "width"), voxelsFor(r.depthM, "depth"), voxelsFor(heightM, "height"));
  VoxelSolid& s = r.solid;

  // The rectangle each view sees of a voxel (fractions of the cropped view, rows from its top)
  const auto frac = [](int i, int n) { return std::pair{static_cast<double>(i) / n, static_cast<double>(i + 1) / n}; };
  const auto sideRect = [&](int, int y, int z) {
    const auto [u0, u1] = frac(y, s.sizeY);
    const auto [w0, w1] = frac(s.sizeZ - 1 - z, s.sizeZ);
    return side.rect(u0, u1, w0, w1);
  };
  const auto frontRect = [&](int x, int, int z) {
    const auto [u0, u1] = frac(s.sizeX - 1 - x, s.sizeX);
    const auto [w0, w1] = frac(s.sizeZ - 1 - z, s.sizeZ);
    return front.rect(u0, u1, w0, w1);
  };
  const auto topRect = [&](int x, int y, int) {
    const auto [u0, u1] = frac(x, s.sizeX);
    const auto [w0, w1] = frac(s.sizeY - 1 - y, s.sizeY);
    return top.rect(u0, u1, w0, w1);
  };

  // Carve: a voxel stays where all three silhouettes cover it
  for (int z = 0; z < s.sizeZ; ++z)
    for (int y = 0; y < s.sizeY; ++y)
      for (int x = 0; x < s.sizeX; ++x)
        if (side.covers(sideRect(x, y, z)) && front.covers(frontRect(x, y, z)) && top.covers(topRect(x, y, z)))
          s.rgba[s.index(x, y, z)] = 0xFF000000u;

  // Colour: an open face up takes the top's colour, else one to the side the side's, else one to
  // the front or back the front's
  const auto open = [&](int x, int y, int z) {
    return x < 0 || y < 0 || z < 0 || x >= s.sizeX || y >= s.sizeY || z >= s.sizeZ || !s.filled(x, y, z);
  };
  std::vector<std::uint32_t> coloured = s.rgba;
  for (int z = 0; z < s.sizeZ; ++z)
    for (int y = 0; y < s.sizeY; ++y)
      for (int x = 0; x < s.sizeX; ++x) {
        if (!s.filled(x, y, z)) continue;
        std::uint32_t& c = coloured[s.index(x, y, z)];
        if (open(x, y, z + 1)) {
          c = top.colour(topRect(x, y, z)), ++r.fromTop;
        } else if (open(x - 1, y, z) || open(x + 1, y, z)) {
          c = side.colour(sideRect(x, y, z)), ++r.fromSide;
        } else if (open(x, y - 1, z) || open(x, y + 1, z)) {
          c = front.colour(frontRect(x, y, z)), ++r.fromFront;
        } else {
          c = side.colour(sideRect(x, y, z)), ++r.hidden;
        }
      }
  s.rgba = std::move(coloured);
  return r;
}

}  // namespace fieldcast::core
