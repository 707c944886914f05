#pragma once
// Lighting a frame by the sun of the moment (RenderSettings::sun) although the terrain's colours
// were baked lit by another (RenderSettings::colourSun): a colour is scaled by the light its
// surface gets now over the light it got when baked (ig_core/README.md, "Sun and time of day").
// The procedural colours bake light(n) = (1 − h) + h·max(0, n·s)/sin(e) for a surface of normal n,
// a sun s at elevation e and a hillshade share h (flat ground keeps its palette colour); now the
// sky's share is scaled by the daylight left at the sun's elevation and the direct share by what
// is left of the sun's disc. With the colours' own sun every factor is exactly 1, so the picture
// is the stored colours to the bit.

#include <ig_core/RenderSettings.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fieldcast::core {

/// Unit vector towards a sun (x east, y north, z up).
inline glm::dvec3 towardsSun(const SunDirection& sun) noexcept {
  const double az = sun.azimuthDeg * std::numbers::pi / 180.0;
  const double el = sun.elevationDeg * std::numbers::pi / 180.0;
  return {std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el)};
}

/// The slope along one axis at a voxel from its two neighbours' height differences (below: here −
/// the one before, above: the one after − here): the smaller of the two when they agree in sign,
/// else 0 (minmod). On smooth ground that is the slope; beside a stick (a roof or a tree standing
/// on the neighbour) it is the ground's side, not a cliff.
inline float minmodSlope(float below, float above) noexcept {
  // Selects, not branches: on rough ground the signs are a coin toss.
  const float smaller = std::fabs(below) < std::fabs(above) ? below : above;
  return below * above > 0.0f ? smaller : 0.0f;
}

class TerrainLight {
 public:
  /// The sky's share of the light on the models entities are drawn from (the rest is the sun's).
  static constexpr double kEntityAmbient = 0.55;

  explicit TerrainLight(const RenderSettings& s) noexcept
      : mRelit(!sameSun(s.sun, s.colourSun)),
        mHillshade(std::clamp(s.colourHillshade, 0.0, 1.0)),
        mToSun(towardsSun(s.sun)),
        mToColourSun(
            towardsSun(SunDirection{s.colourSun.azimuthDeg, std::clamp(s.colourSun.elevationDeg, 1.0, 90.0)})) {
    if (!mRelit) return;  // every factor stays exactly 1
    // Relative to the colours' own: a colour sun low enough to dim them (under 10°) already did.
    const double colourElevation = std::clamp(s.colourSun.elevationDeg, 1.0, 90.0);
    mSky = static_cast<float>(daylight(s.sun.elevationDeg) / daylight(colourElevation));
    mDirect = sunDisc(s.sun.elevationDeg) / sunDisc(colourElevation);
    mFlat = static_cast<float>(lightNow(glm::dvec3{0.0, 0.0, 1.0}) / lightBaked(glm::dvec3{0.0, 0.0, 1.0}));
    mNowSky = static_cast<float>((1.0 - mHillshade) * mSky);
    mNowSun = static_cast<float>(mHillshade * mDirect / mToColourSun.z);
    mBakedSky = static_cast<float>(1.0 - mHillshade);
    mBakedSun = static_cast<float>(mHillshade / mToColourSun.z);
    for (int k = 0; k < 3; ++k) {
      mSun[k] = static_cast<float>(mToSun[k]);
      mColourSun[k] = static_cast<float>(mToColourSun[k]);
    }
  }

  /// True when terrain colours are scaled (the sun is not the colours' own).
  bool relit() const noexcept { return mRelit; }

  /// The factor for terrain colour on ground sloping dzdx (rise east per metre) and dzdy (north):
  /// lightNow(n) / lightBaked(n) for n = (−dzdx, −dzdy, 1) / len, both multiplied by len (one
  /// square root, one division; the caster asks twice per crossing it colours).
  float terrain(float dzdx, float dzdy) const noexcept {
    if (!mRelit) return 1.0f;
    const float len = std::sqrt(dzdx * dzdx + dzdy * dzdy + 1.0f);
    const float now = mNowSky * len + mNowSun * std::max(0.0f, mSun[2] - dzdx * mSun[0] - dzdy * mSun[1]);
    const float baked =
        mBakedSky * len + mBakedSun * std::max(0.0f, mColourSun[2] - dzdx * mColourSun[0] - dzdy * mColourSun[1]);
    return now / std::max(baked, 0.05f * len);  // full hillshade leaves slopes facing away black
  }

  /// The factor for colours that carry no light of their own (sticks, the base plane): level
  /// ground's light now over its baked light.
  float flat() const noexcept { return mFlat; }

  /// The daylight left for the sky and the haze colour (1 by day, 0.05 at night).
  float sky() const noexcept { return mSky; }

  /// The light on a model's face of unit normal n (entities): the sky's share plus the sun's.
  double model(const glm::dvec3& n) const noexcept {
    return kEntityAmbient * mSky + (1.0 - kEntityAmbient) * mDirect * std::max(0.0, glm::dot(n, mToSun));
  }

 private:
  // The same sun written two ways (azimuth −45° is 315°).
  static bool sameSun(const SunDirection& a, const SunDirection& b) noexcept {
    return a.elevationDeg == b.elevationDeg && std::remainder(a.azimuthDeg - b.azimuthDeg, 360.0) == 0.0;
  }
  // Daylight: full with the sun 10° up, falling to 5% (night) at 6° below the horizon (civil dusk).
  static double daylight(double elevationDeg) noexcept { return 0.05 + 0.95 * smoothstep(-6.0, 10.0, elevationDeg); }
  // What reaches the ground of the sun's disc: gone a degree below the horizon, whole 5° up.
  static double sunDisc(double elevationDeg) noexcept { return smoothstep(-1.0, 5.0, elevationDeg); }
  static double smoothstep(double a, double b, double x) noexcept {
    const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
  }
  double lightNow(const glm::dvec3& n) const noexcept {
    return (1.0 - mHillshade) * mSky + mHillshade * mDirect * std::max(0.0, glm::dot(n, mToSun)) / mToColourSun.z;
  }
  double lightBaked(const glm::dvec3& n) const noexcept {
    const double baked = (1.0 - mHillshade) + mHillshade * std::max(0.0, glm::dot(n, mToColourSun)) / mToColourSun.z;
    return std::max(baked, 0.05);  // full hillshade leaves slopes facing away black: no colour to scale
  }

  bool mRelit;
  double mHillshade;
  glm::dvec3 mToSun;
  glm::dvec3 mToColourSun;
  float mSky = 1.0f;
  double mDirect = 1.0;
  float mFlat = 1.0f;
  // terrain()'s constants: the sky's and the sun's shares now and when baked, the suns in float.
  float mNowSky = 1.0f, mNowSun = 0.0f, mBakedSky = 1.0f, mBakedSun = 0.0f;
  float mSun[3] = {0.0f, 0.0f, 1.0f}, mColourSun[3] = {0.0f, 0.0f, 1.0f};
};

}  // namespace fieldcast::core
