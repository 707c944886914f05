// The part of a rolled frame its display samples: a point test, and the rows each column renders.
#include <fieldcast/Frame.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace fieldcast {

namespace {

struct Span {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  bool empty() const noexcept { return !(lo <= hi); }
  void add(double a, double b) noexcept {
    lo = std::min(lo, a);
    hi = std::max(hi, b);
  }
};

// The t with lo ≤ a + b·t ≤ hi.
Span solve(double a, double b, double lo, double hi) noexcept {
  if (std::abs(b) < 1e-12) {
    if (a >= lo && a <= hi) return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    return {};
  }
  const double t0 = (lo - a) / b, t1 = (hi - a) / b;
  return {std::min(t0, t1), std::max(t0, t1)};
}

// The frame rows (continuous) of the footprint on the frame's vertical line at pixel x `u`.
Span rowsAt(const FrameFootprint& f, double u) noexcept {
  // Display normalised (x, y) lands at frame normalised (c·x − s·y, s·x + c·y) (layoutFrame), so
  // frame (X, Y) comes from (c·X + s·Y, −s·X + c·Y).
  const double c = f.cosRoll, s = f.sinRoll;
  const double x = (u - f.cxPx) / f.fxPx;
  const Span a = solve(c * x, s, f.xMin, f.xMax);
  const Span b = solve(-s * x, c, f.yMin, f.yMax);
  const Span y{std::max(a.lo, b.lo), std::min(a.hi, b.hi)};
  if (y.empty()) return {};
  return {f.cyPx + y.lo * f.fyPx, f.cyPx + y.hi * f.fyPx};
}

// The turned window's corners, frame pixels.
std::array<glm::dvec2, 4> corners(const FrameFootprint& f) noexcept {
  std::array<glm::dvec2, 4> out;
  int n = 0;
  for (const double x : {f.xMin, f.xMax}) {
    for (const double y : {f.yMin, f.yMax}) {
      out[static_cast<std::size_t>(n++)] = {f.cxPx + (f.cosRoll * x - f.sinRoll * y) * f.fxPx,
                                            f.cyPx + (f.sinRoll * x + f.cosRoll * y) * f.fyPx};
    }
  }
  return out;
}

}  // namespace

bool FrameFootprint::contains(glm::dvec2 px) const noexcept {
  const bool inFrame = px.x >= 0.0 && px.x <= widthPx && px.y >= 0.0 && px.y <= heightPx;  // false for NaN
  if (whole || !inFrame) return inFrame;
  const double fx = (px.x - cxPx) / fxPx, fy = (px.y - cyPx) / fyPx;
  const double x = cosRoll * fx + sinRoll * fy, y = -sinRoll * fx + cosRoll * fy;
  return x >= xMin && x <= xMax && y >= yMin && y <= yMax;
}

RowRun FrameFootprint::rows(int u) const noexcept {
  if (whole) return {0, heightPx};
  // A bilinear sample at x reads columns ⌊x − ½⌋ and the one after: column u serves samples with
  // x in [u − ½, u + 1½]. Over that strip the convex footprint's rows span its ends' rows and any
  // corner inside it.
  const double left = u - 0.5, right = u + 1.5;
  Span y = rowsAt(*this, left);
  const Span atRight = rowsAt(*this, right);
  if (!atRight.empty()) y.add(atRight.lo, atRight.hi);
  const std::array<glm::dvec2, 4> corner = corners(*this);
  for (const glm::dvec2& p : corner) {
    if (p.x >= left && p.x <= right) y.add(p.y, p.y);
  }
  if (y.empty()) {
    // The strip misses the footprint: the rows beside the corner nearest it
    const auto nearest = std::min_element(corner.begin(), corner.end(), [&](const glm::dvec2& a, const glm::dvec2& b) {
      return std::abs(a.x - (u + 0.5)) < std::abs(b.x - (u + 0.5));
    });
    y = {nearest->y, nearest->y};
  }
  // A sample at y reads rows ⌊y − ½⌋ and the one after
  const double first = std::floor(std::clamp(y.lo, 0.0, static_cast<double>(heightPx)) - 0.5);
  const double last = std::floor(std::clamp(y.hi, 0.0, static_cast<double>(heightPx)) - 0.5) + 1.0;
  RowRun run{static_cast<int>(std::max(first, 0.0)),
             static_cast<int>(std::min(last + 1.0, static_cast<double>(heightPx)))};
  return run;  // never empty: first ≤ heightPx − 1 and last ≥ first + 1
}

}  // namespace fieldcast
