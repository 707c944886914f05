#pragma once
// The post-rendering processor's per-field step (DESIGN.md §3): one Field from the newest frame,
// the pose at the field's display time, and the field's parity — warp, AGC, format conversion.
// Everything is allocated at construction; produce() allocates nothing and never throws.

#include <prp_warp/FieldAssembly.h>
#include <prp_warp/FieldClock.h>
#include <prp_warp/PostProcess.h>
#include <prp_warp/Warp.h>

#include <fieldcast/Field.h>
#include <fieldcast/Frame.h>
#include <fieldcast/Image.h>
#include <fieldcast/Pose.h>

#include <atomic>
#include <cstdint>
#include <memory>

namespace fieldcast::warp {

/// Settings of a FieldWarper.
struct FieldWarperConfig {
  WarpKind warp = WarpKind::Quadratic;
  int rasterWidthPx = 720;  ///< output raster (whole interlaced frame)
  int rasterHeightPx = 486;
  PixelFormat outputFormat = PixelFormat::Uyvy422;
  int maxFrameWidthPx = 1024;  ///< largest frame the flicker filter handles without allocating
  int maxFrameHeightPx = 768;
  bool flickerFilter = false;
  AutoGainConfig autoGain;
  Mirror mirror = Mirror::None;  ///< how the fields are mirrored at start (setMirror changes it)
};

/// Which field to make.
struct FieldSpec {
  std::uint64_t fieldNumber = 0;
  TimePoint displayTime{};
  FieldParity parity = FieldParity::Progressive;
  bool renumbered = false;  ///< see Field::renumbered
  /// The spec of a clock tick.
  static FieldSpec of(const FieldTick& tick) noexcept {
    return {tick.fieldNumber, tick.displayTime, tick.parity, tick.renumbered};
  }
};

/// How producing one field went. Every status still yields a complete field (black when there
/// was nothing to show): the display never waits.
enum class FieldStatus : std::uint8_t {
  Ok,
  NoFrame,    ///< no frame yet (empty image): black field
  BadFrame,   ///< the frame was inconsistent: black field
  BadOutput,  ///< the output Field could not take this shape without allocating: left untouched
  /// The field's camera is beyond the frame's reach (beyondWarpReach: a reposition, such as a
  /// host moving the ownship kilometres at once): the output's previous picture is shown again
  /// with its source frame's number and pose time (of an interlaced raster, the other field's
  /// rows), black when there was none, until a frame rendered near the new pose arrives.
  Held,
};

/// The fastest the eye moves between poses of one flight (m/s): a jump further than this speed
/// covers between the frame's pose time and the field's display time is a reposition.
inline constexpr double kFastestEyeMps = 1000.0;

/// True when a field's camera at `pose`, displayed at `displayTime`, is a reposition away from
/// where `frame` was rendered, so that a warp of it would mean nothing: it moved further than
/// half the range of the nearest surface the frame's control points saw (the warp's parallax
/// error grows with that ratio) and further than kFastestEyeMps could carry it in the time
/// between (so fast flight near the ground, or an entity close to the eye, is still warped; a
/// host moving the ownship kilometres in one message is not). A frame that saw only sky is never
/// out of reach. RT-safe.
bool beyondWarpReach(const Frame& frame, const Pose& pose, TimePoint displayTime) noexcept;

/// Running totals, readable from any thread.
struct FieldWarperCounters {
  std::atomic<std::uint64_t> fields{0};
  std::atomic<std::uint64_t> fitFallbacks{0};
  /// fitFallbacks by FallbackReason (index 0, None, stays 0).
  std::atomic<std::uint64_t> fallbacksByReason[5]{};
  std::atomic<std::uint64_t> marginViolations{0};  ///< output pixels, summed over fields
  std::atomic<std::uint64_t> fieldsWithViolations{0};
  std::atomic<std::uint64_t> blackFields{0};  ///< NoFrame or BadFrame
  std::atomic<std::uint64_t> heldFields{0};   ///< Held: the previous picture again
};

/// Produces fields. One instance per field thread.
class FieldWarper {
 public:
  /// Allocates the warp and every buffer. Throws std::invalid_argument on a bad config.
  explicit FieldWarper(const FieldWarperConfig& config);

  /// A Field whose image is allocated for any parity of this raster and output format.
  Field makeField() const;

  /// Warps `frame` to `pose`, the camera pose at `spec.displayTime` (the caller's motion model
  /// predicts it; the PRP does not), into `out` (made by makeField()). RT-safe: no allocation,
  /// noexcept.
  FieldStatus produce(const Frame& frame, const Pose& pose, const FieldSpec& spec, Field& out) noexcept;

  const FieldWarperConfig& config() const noexcept { return mConfig; }
  const Warp& warp() const noexcept { return *mWarp; }
  const FieldWarperCounters& counters() const noexcept { return mCounters; }
  /// Mirrors the fields from the next one on. Any thread.
  void setMirror(Mirror mirror) noexcept { mMirror.store(mirror, std::memory_order_relaxed); }
  Mirror mirror() const noexcept { return mMirror.load(std::memory_order_relaxed); }
  /// The gain the AGC applied to the last field warped, as applied (in steps of 1/65536; 1 when
  /// off).
  double gain() const noexcept { return mAppliedGain; }

 private:
  /// Reshapes `image` without allocating (its capacity was reserved); false if it cannot.
  static bool reshape(Image& image, int widthPx, int heightPx, PixelFormat format, std::size_t reservedBytes) noexcept;
  const Image& flickerFiltered(const Frame& frame) noexcept;

  FieldWarperConfig mConfig;
  std::unique_ptr<Warp> mWarp;
  AutoGain mAutoGain;
  double mAppliedGain = 1.0;
  FieldAssembly mAssembly;  // takes the warp's pieces into the output field
  Image mFiltered;          // the flicker-filtered copy of the current frame
  std::uint64_t mFilteredFrameNumber = 0;
  TimePoint mFilteredPoseTime{};
  bool mHaveFiltered = false;
  TimePoint mLastDisplayTime{};
  bool mHaveLast = false;
  FieldWarperCounters mCounters;
  std::atomic<Mirror> mMirror;
};

}  // namespace fieldcast::warp
