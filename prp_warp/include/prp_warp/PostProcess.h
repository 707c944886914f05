#pragma once
// Post-processing of a warped field, as the seed's video processor did (DESIGN.md §3): automatic
// gain control smoothed over time, an interlace flicker filter, and conversion to the output
// pixel format. Scaling to the output raster is folded into the warp's map (OutputGeometry.h),
// which saves a second resample and its blur.

#include <fieldcast/Frame.h>
#include <fieldcast/Image.h>
#include <fieldcast/Time.h>

#include <array>
#include <cstdint>

namespace fieldcast::warp {

/// Settings of the automatic gain control.
struct AutoGainConfig {
  bool enabled = false;
  double targetMeanLevel = 110.0;  ///< mean luma (0..255) the gain steers towards
  double timeConstantS = 0.5;      ///< first-order smoothing of the gain over time
  double minGain = 0.5;
  double maxGain = 4.0;
};

/// Automatic gain control: measures the mean luma of each field, steers a gain towards
/// target/mean with a first-order low-pass in time (so a bright flash or a cloud does not pump),
/// and applies it to every 8-bit value v as min(255, (v · gainQ16 + 2^15) >> 16).
class AutoGain {
 public:
  explicit AutoGain(const AutoGainConfig& config = {}) noexcept;
  /// Measures `field` (Grey8 or Rgb8) and updates the gain for `elapsed` time since the last
  /// field, without applying it (convertPixels applies it as it converts). Returns false, the gain
  /// unchanged, when disabled or for an empty or UYVY field. RT-safe.
  bool update(const Image& field, Nanoseconds elapsed) noexcept;
  /// update() with the field's mean luma (0..255) measured by the caller, as meanLuma(field, 2)
  /// does. Returns false, the gain unchanged, when disabled. RT-safe.
  bool updateFromMean(double meanLuma, Nanoseconds elapsed) noexcept;
  /// update(), then the gain applied to `field` in place through a 256-entry table. RT-safe.
  void process(Image& field, Nanoseconds elapsed) noexcept;
  /// The gain as last updated.
  double gain() const noexcept { return mGain; }
  bool enabled() const noexcept { return mConfig.enabled; }
  /// The gain as applied, in 1/65536 (65536 when disabled).
  std::int32_t gainQ16() const noexcept;
  void reset() noexcept;

 private:
  void rebuildTable() noexcept;

  AutoGainConfig mConfig;
  double mGain = 1.0;
  double mTableGain = -1.0;
  std::int32_t mGainQ16 = 1 << 16;
  std::array<std::uint8_t, 256> mTable{};
};

/// Mean luma (BT.601 weights, 0..255) of an Rgb8 or Grey8 image, from every `step`-th pixel of
/// every `step`-th row (0 for other formats). R'G'B' rows in SIMD lanes at the dispatched level
/// for steps 1 and 2. RT-safe.
double meanLuma(const Image& image, int step = 1) noexcept;
/// meanLuma in plain scalar code: the reference the lanes must equal exactly.
double meanLumaReference(const Image& image, int step = 1) noexcept;

/// The interlace flicker filter: a vertical [1 2 1]/4 low-pass across frame rows, which removes
/// the 30 Hz twitter of one-line detail on an interlaced display. It runs once per new frame
/// (frame rows ≈ raster lines), not per field. `dst` must already have the shape and format of
/// `src` (Grey8 or Rgb8). Returns false (dst untouched) otherwise. In SIMD lanes at the
/// dispatched level (fieldcast/SimdLevel.h). RT-safe.
bool flickerFilter(const Image& src, Image& dst) noexcept;

/// flickerFilter in plain C++ only: the judge of its SIMD forms, which give the same bytes.
bool flickerFilterReference(const Image& src, Image& dst) noexcept;

/// Makes `frame.flickerFiltered` from its image (flickerFilter) and sets hasFlickerFiltered, for
/// the frame's producer: a field warper that filters then samples it, and the per-frame filter is
/// off the field thread. Allocates the first time (and when the frame grows). Returns false, with
/// hasFlickerFiltered cleared, for an image it cannot filter (UYVY, empty).
bool makeFlickerFiltered(Frame& frame);

/// Converts `src` (Grey8 or Rgb8) into `dst` of the same size in dst's format: Grey8 (BT.601
/// luma, full range), Rgb8, or UYVY 4:2:2 (BT.601 video range: Y 16..235, Cb/Cr 16..240, chroma
/// averaged over each pixel pair), applying a gain in 1/65536 (AutoGain::gainQ16, taken within
/// [0, 128]) to every value first. Returns false when the shapes or formats do not fit. RGB to
/// UYVY runs in SIMD lanes at the dispatched level (fieldcast/SimdLevel.h). RT-safe.
bool convertPixels(const Image& src, Image& dst, std::int32_t gainQ16 = 1 << 16) noexcept;

/// convertPixels in plain C++ only: the judge of its SIMD forms, which give the same bytes.
bool convertPixelsReference(const Image& src, Image& dst, std::int32_t gainQ16 = 1 << 16) noexcept;

/// How the picture is mirrored on its display: a rear-view mirror, a rear-projection screen (CIGI
/// View Definition's mirror modes).
enum class Mirror : std::uint8_t {
  None,
  Horizontal,  ///< left and right swapped
  Vertical,    ///< top and bottom swapped
  Both,
};
constexpr bool mirrorsColumns(Mirror m) noexcept { return m == Mirror::Horizontal || m == Mirror::Both; }
constexpr bool mirrorsRows(Mirror m) noexcept { return m == Mirror::Vertical || m == Mirror::Both; }

/// Reverses the columns and/or the rows of `image` (Grey8 or Rgb8) in place. RT-safe.
void mirrorInPlace(Image& image, Mirror mirror) noexcept;

/// Fills `image` with black in its format (UYVY black is Y 16, Cb = Cr = 128). RT-safe.
void fillBlack(Image& image) noexcept;

}  // namespace fieldcast::warp
