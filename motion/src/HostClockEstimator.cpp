// Host clock offset and drift from one-way timestamps: the lower-envelope (linear programming)
// skew estimator of Moon, Skelly & Towsley (INFOCOM 1999) over a sliding window.
#include <motion/HostClockEstimator.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace fieldcast::motion {

TimePoint HostClockMapping::toLocal(double hostTimeS) const noexcept {
  if (!valid) return TimePoint{};
  const double dxS = hostTimeS - hostRefS;
  return localRef + fromSeconds(dxS + offsetS + driftRatio * dxS);
}

void HostClockEstimator::reset() noexcept {
  mFirst = 0;
  mSize = 0;
  mMapping = HostClockMapping{};
}

void HostClockEstimator::add(double hostTimeS, TimePoint arrival) noexcept {
  if (!mMapping.valid) {
    mMapping = HostClockMapping{hostTimeS, arrival, 0.0, 0.0, true};
  }
  const double xS = hostTimeS - mMapping.hostRefS;
  const Point p{xS, toSeconds(arrival - mMapping.localRef) - xS};
  if (mSize > 0 && std::floor(xS / kBucketS) == std::floor(point(mSize - 1).xS / kBucketS)) {
    // Same bucket: only its lowest point can hold the minimum-delay line up.
    Point& last = mPoints[(mFirst + mSize - 1) % kWindow];
    if (p.yS < last.yS) last = p;
    fit();
    return;
  }
  if (mSize == kWindow) {  // the oldest makes room
    mFirst = (mFirst + 1) % kWindow;
    --mSize;
  }
  mPoints[(mFirst + mSize) % kWindow] = p;
  ++mSize;
  while (xS - point(0).xS > kWindowSpanS) {
    mFirst = (mFirst + 1) % kWindow;
    --mSize;
  }
  fit();
}

void HostClockEstimator::fit() noexcept {
  const Point& oldest = point(0);
  const Point& newest = point(mSize - 1);

  // The offset under every point for a given drift: the lowest point decides.
  auto lowestOffset = [this](double drift) {
    double a = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < mSize; ++i) a = std::min(a, point(i).yS - drift * point(i).xS);
    return a;
  };

  if (newest.xS - oldest.xS < kMinDriftSpanS) {
    mMapping.offsetS = lowestOffset(mMapping.driftRatio);
    return;
  }

  // Lower convex hull (Andrew's monotone chain; x increases with i).
  std::size_t hullSize = 0;
  double xSum = 0.0;
  for (std::size_t i = 0; i < mSize; ++i) {
    const Point& c = point(i);
    xSum += c.xS;
    while (hullSize >= 2) {
      const Point& a = point(mHull[hullSize - 2]);
      const Point& b = point(mHull[hullSize - 1]);
      const double cross = (b.xS - a.xS) * (c.yS - a.yS) - (b.yS - a.yS) * (c.xS - a.xS);
      if (cross > 0.0) break;  // b stays below the chord a–c
      --hullSize;
    }
    mHull[hullSize++] = i;
  }

  // The hull edge over the mean host time: the line under all points with the least mean gap.
  const double xMean = xSum / static_cast<double>(mSize);
  std::size_t edge = 0;
  while (edge + 2 < hullSize && point(mHull[edge + 1]).xS < xMean) ++edge;
  const Point& a = point(mHull[edge]);
  const Point& b = point(mHull[edge + 1]);
  const double drift = (b.yS - a.yS) / (b.xS - a.xS);
  if (std::abs(drift) <= kMaxDriftRatio) {
    mMapping.driftRatio = drift;
    mMapping.offsetS = a.yS - drift * a.xS;
  } else {
    mMapping.driftRatio = std::clamp(drift, -kMaxDriftRatio, kMaxDriftRatio);
    mMapping.offsetS = lowestOffset(mMapping.driftRatio);
  }
}

}  // namespace fieldcast::motion
