#include <ig_core/RenderConfig.h>

#include <algorithm>

namespace fieldcast::core {

RenderConfig readRenderConfig(ConfigReader& t, int defaultWidthPx, int defaultHeightPx) {
  RenderConfig c;
  RenderSettings& s = c.settings;
  c.threads = static_cast<int>(t.integer("threads", c.threads, 0, 256));
  c.maxRateHz = t.number("max_rate_hz", c.maxRateHz, 0.0, 1000.0);
  c.hfovDeg = t.number("fov_deg", c.hfovDeg, 5.0, 150.0);
  s.marginFraction = t.number("margin", s.marginFraction, 0.0, 1.0);
  c.controller.target = fromSeconds(t.number("target_frame_ms", 0.0, 0.0, 1000.0) * 1e-3);
  s.quality = t.number("quality", s.quality, 0.25, 16.0);
  s.maxAnisotropy = t.number("max_anisotropy", s.maxAnisotropy, 0.0, 64.0);
  const double controllerAnisotropy = t.number("controller_anisotropy", 2.0, 0.0, 64.0);
  // A fixed grazing rule stays on; otherwise the controller may turn it on before it coarsens quality.
  c.controller.grazingAnisotropy = s.maxAnisotropy > 0.0 ? 0.0 : controllerAnisotropy;
  s.rangeImage = t.boolean("range_image", s.rangeImage);
  s.colourMode = t.boolean("grey", false) ? FrameColour::Grey : FrameColour::Rgb;
  c.widthPx = static_cast<int>(t.integer("width", defaultWidthPx, 16, 8192));
  c.heightPx = static_cast<int>(t.integer("height", defaultHeightPx, 16, 8192));
  c.visibilityGiven = t.has("visibility_m");
  if (c.visibilityGiven) s.hazeRangeM = t.number("visibility_m", s.hazeRangeM, 0.0, 1e7);
  s.colourSun.azimuthDeg = t.number("colour_sun_azimuth_deg", s.colourSun.azimuthDeg, -360.0, 360.0);
  s.colourSun.elevationDeg = t.number("colour_sun_elevation_deg", s.colourSun.elevationDeg, 1.0, 90.0);
  s.colourHillshade = t.number("colour_hillshade", s.colourHillshade, 0.0, 1.0);
  // Without a sun of its own the frame is lit as the colours were: drawn as stored.
  s.sun.azimuthDeg = t.number("sun_azimuth_deg", s.colourSun.azimuthDeg, -360.0, 360.0);
  s.sun.elevationDeg = t.number("sun_elevation_deg", s.colourSun.elevationDeg, -90.0, 90.0);
  t.finish();
  return c;
}

double defaultVisibilityM(double extentM) noexcept { return std::max(3000.0, 0.75 * extentM); }

}  // namespace fieldcast::core
