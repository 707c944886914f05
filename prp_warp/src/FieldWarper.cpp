// One field: the pose at t_k → warp (of the frame flicker-filtered once per frame) → mirror, AGC and format
// piece by piece as the warp writes.
#include <prp_warp/FieldWarper.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace fieldcast::warp {

FieldWarper::FieldWarper(const FieldWarperConfig& config)
    : mConfig(config),
      mWarp(makeWarp(config.warp, config.rasterWidthPx, config.rasterHeightPx)),
      mAutoGain(config.autoGain),
      mAssembly(config.rasterWidthPx),
      mMirror(config.mirror) {
  if (config.outputFormat == PixelFormat::Uyvy422 && config.rasterWidthPx % 2 != 0) {
    throw std::invalid_argument("field warper: UYVY 4:2:2 output needs an even width, got " +
                                std::to_string(config.rasterWidthPx));
  }
  if (config.maxFrameWidthPx < 2 || config.maxFrameHeightPx < 2) {
    throw std::invalid_argument("field warper: max frame size must be at least 2x2");
  }
  if (config.flickerFilter) mFiltered.resize(config.maxFrameWidthPx, config.maxFrameHeightPx, PixelFormat::Rgb8);
}

Field FieldWarper::makeField() const {
  Field f;
  // Progressive needs every row; the image is reshaped (never grown) per field
  f.image.resize(mConfig.rasterWidthPx, mConfig.rasterHeightPx, mConfig.outputFormat);
  f.rasterHeightPx = mConfig.rasterHeightPx;
  return f;
}

bool FieldWarper::reshape(Image& image, int widthPx, int heightPx, PixelFormat format,
                          std::size_t reservedBytes) noexcept {
  if (image.widthPx() == widthPx && image.heightPx() == heightPx && image.format() == format) return true;
  // Reshape only within the bytes reserved up front: vector::assign keeps the allocation then
  if (rowBytes(format, widthPx) * static_cast<std::size_t>(heightPx) > reservedBytes) return false;
  try {
    image.resize(widthPx, heightPx, format);
  } catch (...) {
    return false;
  }
  return true;
}

const Image& FieldWarper::flickerFiltered(const Frame& frame) noexcept {
  if (!mConfig.flickerFilter) return frame.image;
  // Made by the frame's producer (makeFlickerFiltered): nothing to do here
  const Image& made = frame.flickerFiltered;
  if (frame.hasFlickerFiltered && made.sameShape(frame.image)) return made;
  if (mHaveFiltered && mFilteredFrameNumber == frame.frameNumber && mFilteredPoseTime == frame.poseTime &&
      mFiltered.sameShape(frame.image))
    return mFiltered;
  // A frame larger than the reserved buffer is warped unfiltered rather than allocating
  const std::size_t reserved =
      rowBytes(PixelFormat::Rgb8, mConfig.maxFrameWidthPx) * static_cast<std::size_t>(mConfig.maxFrameHeightPx);
  if (!reshape(mFiltered, frame.image.widthPx(), frame.image.heightPx(), frame.image.format(), reserved) ||
      !flickerFilter(frame.image, mFiltered)) {
    mHaveFiltered = false;
    return frame.image;
  }
  mHaveFiltered = true;
  mFilteredFrameNumber = frame.frameNumber;
  mFilteredPoseTime = frame.poseTime;
  return mFiltered;
}

bool beyondWarpReach(const Frame& frame, const Pose& pose, TimePoint displayTime) noexcept {
  double nearestSq = std::numeric_limits<double>::infinity();
  for (const ControlPoint& cp : frame.controlPoints) {
    if (cp.kind != ControlPointKind::Surface) continue;
    const glm::dvec3 d = cp.world - frame.pose.positionM;
    nearestSq = std::min(nearestSq, glm::dot(d, d));
  }
  const glm::dvec3 moved = pose.positionM - frame.pose.positionM;
  const double movedSq = glm::dot(moved, moved);
  const double reachM = kFastestEyeMps * std::abs(toSeconds(displayTime - frame.poseTime));
  return movedSq > 0.25 * nearestSq && movedSq > reachM * reachM;
}

FieldStatus FieldWarper::produce(const Frame& frame, const Pose& pose, const FieldSpec& spec, Field& out) noexcept {
  const int rows = fieldRowCount(spec.parity, mConfig.rasterHeightPx);
  // `out` comes from makeField(): room for a progressive field in the output format
  const std::size_t outReserved =
      rowBytes(mConfig.outputFormat, mConfig.rasterWidthPx) * static_cast<std::size_t>(mConfig.rasterHeightPx);
  if (out.image.widthPx() != mConfig.rasterWidthPx) return FieldStatus::BadOutput;  // not from makeField()
  if (!reshape(out.image, mConfig.rasterWidthPx, rows, mConfig.outputFormat, outReserved))
    return FieldStatus::BadOutput;
  out.parity = spec.parity;
  out.rasterHeightPx = mConfig.rasterHeightPx;
  out.fieldNumber = spec.fieldNumber;
  out.renumbered = spec.renumbered;
  out.displayTime = spec.displayTime;
  const std::uint64_t shownFrameNumber = out.sourceFrameNumber;  // what a held field shows again
  const TimePoint shownPoseTime = out.sourcePoseTime;
  out.sourceFrameNumber = frame.frameNumber;
  out.sourcePoseTime = frame.poseTime;
  out.marginViolations = 0;
  mCounters.fields.fetch_add(1, std::memory_order_relaxed);

  auto black = [&](FieldStatus status) noexcept {
    fillBlack(out.image);
    mCounters.blackFields.fetch_add(1, std::memory_order_relaxed);
    return status;
  };
  if (frame.image.empty()) return black(FieldStatus::NoFrame);
  if (beyondWarpReach(frame, pose, spec.displayTime)) {
    mCounters.heldFields.fetch_add(1, std::memory_order_relaxed);
    if (!mHaveLast) fillBlack(out.image);  // nothing shown yet to show again
    out.sourceFrameNumber = shownFrameNumber;
    out.sourcePoseTime = shownPoseTime;
    return FieldStatus::Held;
  }
  const PixelFormat workFormat = frame.image.format();
  if (workFormat != PixelFormat::Rgb8 && workFormat != PixelFormat::Grey8) return black(FieldStatus::BadFrame);

  // Warp to the pose at the field's own display time. Mirrored top to bottom, raster line y shows
  // line H−1−y: of an even raster's other field, so that field's rows are warped (at this
  // field's pose) and then reversed.
  const Mirror mirror = mMirror.load(std::memory_order_relaxed);
  FieldParity sampled = spec.parity;
  if (mirrorsRows(mirror) && spec.parity != FieldParity::Progressive && mConfig.rasterHeightPx % 2 == 0) {
    sampled = spec.parity == FieldParity::Top ? FieldParity::Bottom : FieldParity::Top;
  }
  // Each piece the warp writes is mirrored, measured and converted at once (FieldAssembly), so
  // the gain is the one measured up to the field before: one field's lag, as a camera's AGC has
  const std::int32_t gainQ16 = mAutoGain.gainQ16();
  mAssembly.start(out.image, mirror, gainQ16, mAutoGain.enabled());
  const WarpResult r = mWarp->warp(frame, flickerFiltered(frame), pose, sampled, mAssembly.rows(workFormat));
  if (r.status != WarpStatus::Ok) return black(FieldStatus::BadFrame);
  mAppliedGain = gainQ16 / 65536.0;
  if (r.fellBack) {
    mCounters.fitFallbacks.fetch_add(1, std::memory_order_relaxed);
    mCounters.fallbacksByReason[static_cast<int>(r.fallbackReason)].fetch_add(1, std::memory_order_relaxed);
  }
  if (r.marginViolations) {
    mCounters.marginViolations.fetch_add(r.marginViolations, std::memory_order_relaxed);
    mCounters.fieldsWithViolations.fetch_add(1, std::memory_order_relaxed);
  }
  out.marginViolations = r.marginViolations;

  // The gain for the next field, over the time since the previous one
  const Nanoseconds elapsed =
      mHaveLast ? std::clamp(spec.displayTime - mLastDisplayTime, Nanoseconds{0}, Nanoseconds{1'000'000'000})
                : Nanoseconds{0};
  mLastDisplayTime = spec.displayTime;
  mHaveLast = true;
  mAutoGain.updateFromMean(mAssembly.meanLuma(), elapsed);
  return FieldStatus::Ok;
}

}  // namespace fieldcast::warp
