#pragma once
// An analytic test scene for the warps: a textured ground plane z = 0 under a sky whose colour
// depends only on direction. Frames and ground-truth fields are rendered exactly by ray–plane
// intersection, so every warp can be judged against the true image at the field's pose.

#include <prp_warp/OutputGeometry.h>

#include <fieldcast/Conventions.h>
#include <fieldcast/Field.h>
#include <fieldcast/Frame.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace fieldcast::warp::test {

/// What a ray sees: a ground point or a sky direction.
struct Hit {
  bool ground = false;
  glm::dvec3 point{0.0};      ///< ground point (metres) when ground
  glm::dvec3 direction{0.0};  ///< unit ray direction
  double rangeM = std::numeric_limits<double>::infinity();
};

inline Hit castRay(const glm::dvec3& origin, const glm::dvec3& dir) {
  Hit h;
  h.direction = dir;
  if (dir.z < -1e-9 && origin.z > 0.0) {
    const double t = -origin.z / dir.z;
    h.ground = true;
    h.point = origin + t * dir;
    h.rangeM = t;  // dir is unit: t is the range
  }
  return h;
}

/// Ground texture: smooth detail at several scales (grey levels 0..255 per channel).
inline glm::dvec3 groundColour(const glm::dvec3& p) {
  const double a = std::sin(p.x * 0.45) * std::sin(p.y * 0.35);
  const double b = std::sin(p.x * 0.23 + 1.0) + std::cos(p.y * 0.31);
  const double c = std::sin((p.x + p.y) * 0.051);
  const double base = 120.0 + 45.0 * a + 25.0 * b + 20.0 * c;
  return {base + 10.0 * c, base - 8.0 * b, base * 0.8 + 15.0 * a};
}

inline glm::dvec3 skyColour(const glm::dvec3& dir) {
  const double e = std::clamp(dir.z, 0.0, 1.0);
  return {150.0 - 60.0 * e, 180.0 - 40.0 * e, 235.0 - 10.0 * e};
}

inline glm::dvec3 shade(const Hit& h) { return h.ground ? groundColour(h.point) : skyColour(h.direction); }

inline std::uint8_t toByte(double v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L)); }

/// Colour seen through continuous pixel `px` of a camera, averaged over `ss`×`ss` sub-samples
/// of the pixel (reduces aliasing in both the frames and the truth alike).
inline glm::dvec3 renderPixel(const Pose& pose, const Intrinsics& k, glm::dvec2 centre, int ss) {
  glm::dvec3 sum{0.0};
  for (int sy = 0; sy < ss; ++sy)
    for (int sx = 0; sx < ss; ++sx) {
      const glm::dvec2 p = centre + glm::dvec2{(sx + 0.5) / ss - 0.5, (sy + 0.5) / ss - 0.5};
      sum += shade(castRay(pose.positionM, pixelRay(pose, k, p)));
    }
  return sum / static_cast<double>(ss * ss);
}

/// A frame of the scene: display window `display` with `margin`, rendered at `pose` (the IG renders
/// without roll, so pass roll 0), with range image and the nine control points.
inline Frame renderFrame(const Pose& pose, const Intrinsics& display, MarginPx margin,
                         PixelFormat format = PixelFormat::Rgb8, int ss = 2, bool withRange = true) {
  const int displayW = display.widthPx, displayH = display.heightPx;
  Frame f;
  f.pose = pose;
  f.margin = margin;
  f.intrinsics = display.withMargin(margin.x, margin.y);
  const int w = f.intrinsics.widthPx, h = f.intrinsics.heightPx;
  f.image.resize(w, h, format);
  if (withRange) f.rangeM.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0.0f);
  for (int y = 0; y < h; ++y) {
    std::uint8_t* row = f.image.row(y);
    for (int x = 0; x < w; ++x) {
      const glm::dvec2 c = pixelCentre(x, y);
      const glm::dvec3 col = renderPixel(pose, f.intrinsics, c, ss);
      if (format == PixelFormat::Rgb8) {
        row[3 * x] = toByte(col.r);
        row[3 * x + 1] = toByte(col.g);
        row[3 * x + 2] = toByte(col.b);
      } else {
        row[x] = toByte((col.r + col.g + col.b) / 3.0);
      }
      if (withRange) {
        const Hit hit = castRay(pose.positionM, pixelRay(pose, f.intrinsics, c));
        f.rangeM[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + x] =
            hit.ground ? static_cast<float>(hit.rangeM) : std::numeric_limits<float>::infinity();
      }
    }
  }
  for (const glm::dvec2& px : controlGridFramePx(displayW, displayH, margin)) {
    const Hit hit = castRay(pose.positionM, pixelRay(pose, f.intrinsics, px));
    ControlPoint cp;
    cp.framePx = px;
    cp.kind = hit.ground ? ControlPointKind::Surface : ControlPointKind::Sky;
    cp.world = hit.ground ? hit.point : hit.direction;
    f.controlPoints.push_back(cp);
  }
  return f;
}

/// The same with a centred display window `hfovRad` wide.
inline Frame renderFrame(const Pose& pose, int displayW, int displayH, MarginPx margin, double hfovRad,
                         PixelFormat format = PixelFormat::Rgb8, int ss = 2, bool withRange = true) {
  return renderFrame(pose, Intrinsics::fromHorizontalFov(displayW, displayH, hfovRad), margin, format, ss, withRange);
}

/// The true field: the rows of `parity` of the raster seen from `pose`, in the frame's format.
/// A small oblique frame of the scene (160×120 display, 16/12 px margins, 60° wide, 30° heading,
/// 15° down from 150 m; no supersampling), rendered once: for tests of the field path that need
/// a picture with terrain and sky, not a particular one.
inline const Frame& obliqueFrame() {
  static const Frame f = renderFrame(Pose{{0.0, 0.0, 150.0}, radians(30.0), radians(-15.0), 0.0}, 160, 120,
                                     MarginPx{16, 12}, radians(60.0), PixelFormat::Rgb8, 1, true);
  return f;
}

inline Image renderTruthField(const Frame& frame, const Pose& pose, int rasterW, int rasterH, FieldParity parity,
                              int ss = 2) {
  const OutputGeometry g = OutputGeometry::of(frame, rasterW, rasterH);
  Image out(rasterW, fieldRowCount(parity, rasterH), frame.image.format());
  for (int r = 0; r < out.heightPx(); ++r) {
    std::uint8_t* row = out.row(r);
    for (int x = 0; x < rasterW; ++x) {
      const glm::dvec3 col = renderPixel(pose, g.raster, pixelCentre(x, rasterRow(parity, r)), ss);
      if (frame.image.format() == PixelFormat::Rgb8) {
        row[3 * x] = toByte(col.r);
        row[3 * x + 1] = toByte(col.g);
        row[3 * x + 2] = toByte(col.b);
      } else {
        row[x] = toByte((col.r + col.g + col.b) / 3.0);
      }
    }
  }
  return out;
}

/// Where the point seen through raster pixel `rasterPx` at `pose` lies in the frame: the
/// frame pixel a perfect warp would sample there.
inline std::optional<glm::dvec2> trueSourcePx(const Frame& frame, const Pose& pose, const OutputGeometry& g,
                                              glm::dvec2 rasterPx) {
  const Hit hit = castRay(pose.positionM, pixelRay(pose, g.raster, rasterPx));
  return hit.ground ? projectPoint(frame.pose, frame.intrinsics, hit.point)
                    : projectDirection(frame.pose, frame.intrinsics, hit.direction);
}

/// Peak signal-to-noise ratio (dB) between two same-shaped 8-bit images.
inline double psnr(const Image& a, const Image& b) {
  double se = 0.0;
  const auto ab = a.bytes();
  const auto bb = b.bytes();
  for (std::size_t i = 0; i < ab.size(); ++i) {
    const double d = static_cast<double>(ab[i]) - static_cast<double>(bb[i]);
    se += d * d;
  }
  const double mse = se / static_cast<double>(ab.size());
  return mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
}

}  // namespace fieldcast::warp::test
