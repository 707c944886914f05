// Warp evaluation in virtual time. Time line of one rate R (period P = 1/R):
//   frame j is started at s_j = t_first − P + j·P for the flight's pose at s_j and becomes
//   available at s_j + P (one frame period of render latency);
//   field k is shown at t_k = t_first + k·T and made from the newest available frame, for the
//   flight's pose at t_k (the motion model is exact here: the evaluation isolates the warp).
// Ground truth of field k: the IG's own frame rendered at the field's pose (unrolled), with the
// field's roll applied by the exact rotation-only homography. Geometric truth at a check pixel:
// the world point the truth frame sees there (its range image), projected into the source frame.
#include "WarpEvaluation.h"

#include <prp_warp/FieldClock.h>
#include <prp_warp/Resample.h>
#include <prp_warp/WarpFit.h>
#include <prp_warp/Warps.h>

#include <fieldcast/Conventions.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace fieldcast::tools {
namespace {

double psnrDb(const Image& a, const Image& b) {
  double se = 0.0;
  const auto ab = a.bytes();
  const auto bb = b.bytes();
  for (std::size_t i = 0; i < ab.size(); ++i) {
    const double d = static_cast<double>(ab[i]) - static_cast<double>(bb[i]);
    se += d * d;
  }
  const double mse = se / static_cast<double>(std::max<std::size_t>(ab.size(), 1));
  return mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const auto i = static_cast<std::size_t>(
      std::clamp(q * static_cast<double>(v.size() - 1), 0.0, static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(i), v.end());
  return v[i];
}

/// The check pixels of a field of `parity`: the pixels at fractions (i + ¼)/n of the raster, away
/// from the 3 × 3 control grid at 5 %, 50 % and 95 %, on the field's own rows.
std::vector<glm::dvec2> checkPixels(const EvaluationSpec& spec, FieldParity parity) {
  std::vector<glm::dvec2> out;
  const int rows = fieldRowCount(parity, spec.rasterHeightPx);
  for (int j = 0; j < spec.checkRows; ++j) {
    const int fieldRow = std::min(rows - 1, static_cast<int>((j + 0.25) / spec.checkRows * rows));
    for (int i = 0; i < spec.checkColumns; ++i) {
      // Pixel centres: every warp's sampling map is compared where it actually samples
      const int column = static_cast<int>((i + 0.25) / spec.checkColumns * spec.rasterWidthPx);
      out.emplace_back(column + 0.5, rasterRow(parity, fieldRow) + 0.5);
    }
  }
  return out;
}

/// Where a perfect warp would sample frame `source` for raster pixel `p` of the truth field.
std::optional<glm::dvec2> trueSourcePx(const TruthField& truth, const Pose& fieldPose, const warp::OutputGeometry& g,
                                       const warp::Homography& toTruthFrame, const Frame& source, glm::dvec2 p) {
  const glm::dvec2 q = toTruthFrame(p);  // truth frame pixel seen at raster p (roll applied)
  const Frame& f = truth.frame;
  const int u = std::clamp(static_cast<int>(std::floor(q.x)), 0, f.intrinsics.widthPx - 1);
  const int v = std::clamp(static_cast<int>(std::floor(q.y)), 0, f.intrinsics.heightPx - 1);
  const float range = f.rangeM[static_cast<std::size_t>(v) * static_cast<std::size_t>(f.intrinsics.widthPx) + u];
  const glm::dvec3 ray = pixelRay(fieldPose, g.raster, p);  // the field's own ray through p
  if (std::isinf(range)) return projectDirection(source.pose, source.intrinsics, ray);
  return projectPoint(source.pose, source.intrinsics, fieldPose.positionM + static_cast<double>(range) * ray);
}

}  // namespace

double minimumClearanceM(const EvaluatedFlight& flight, const core::TerrainView& terrain, const EvaluationSpec& spec) {
  double minimum = std::numeric_limits<double>::infinity();
  const double end = spec.startS + toSeconds(spec.fieldRate.tickOffset(spec.fields));
  for (double t = std::max(0.0, spec.startS - 1.0); t <= end; t += 0.01) {
    const Pose p = flight.poseAtSeconds(t);
    minimum = std::min(minimum, p.positionM.z - terrain.heightAtM(p.positionM.x, p.positionM.y));
  }
  return minimum;
}

std::vector<RateResult> evaluateFlight(const EvaluatedFlight& flight, core::Renderer& renderer,
                                       const EvaluationSpec& spec, const std::vector<double>& ratesHz,
                                       const Progress& progress) {
  const int totalSteps = spec.fields * (1 + static_cast<int>(ratesHz.size()));  // truth, then each rate
  int steps = 0;
  auto step = [&] {
    if (progress) progress(++steps, totalSteps);
  };
  const Intrinsics display =
      Intrinsics::fromHorizontalFov(spec.rasterWidthPx, spec.rasterHeightPx, radians(spec.hfovDeg));
  const TimePoint tFirst{fromSeconds(spec.startS)};
  const double lastS = spec.startS + toSeconds(spec.fieldRate.tickOffset(spec.fields));
  if (lastS > flight.durationS()) {
    throw std::runtime_error("flight '" + flight.name() + "' lasts " + std::to_string(flight.durationS()) +
                             " s, the evaluation needs " + std::to_string(lastS) + " s (fewer --fields?)");
  }

  // The field schedule, from the field clock in virtual time (never sleeps for real)
  VirtualClock clock(tFirst - std::chrono::milliseconds(100));
  warp::FieldClockConfig clockConfig;
  clockConfig.rate = spec.fieldRate;
  clockConfig.scan = spec.scan;
  clockConfig.order = spec.order;
  warp::FieldClock fieldClock(clock, clockConfig, tFirst);
  std::vector<warp::FieldTick> ticks;
  for (int k = 0; k < spec.fields; ++k) ticks.push_back(fieldClock.next());

  // Ground truth of every field, shared by all rates
  std::vector<TruthField> truths;
  std::vector<Pose> fieldPoses;
  warp::RowScratch scratch(spec.rasterWidthPx);
  for (const warp::FieldTick& tick : ticks) {
    const Pose pose = flight.poseAt(tick.displayTime);
    fieldPoses.push_back(pose);
    TruthField t;
    t.frame = renderer.render(core::ViewRequest{pose, tick.displayTime, display, tick.fieldNumber, {}});
    t.pixels.resize(spec.rasterWidthPx, fieldRowCount(tick.parity, spec.rasterHeightPx), t.frame.image.format());
    const warp::OutputGeometry g = warp::OutputGeometry::of(t.frame, spec.rasterWidthPx, spec.rasterHeightPx);
    warp::resampleHomography(t.frame.image, warp::rotationHomography(t.frame, pose, g), tick.parity,
                             spec.rasterHeightPx, t.pixels, scratch);
    truths.push_back(std::move(t));
    step();
  }

  // The pose each field is warped to, per FieldPoses of the spec, and how far it is from the truth
  const std::size_t modes = spec.fieldPoses.size();
  std::vector<std::vector<Pose>> warpPoses(modes);
  std::vector<PoseError> meanPoseErrors(modes), maxPoseErrors(modes);
  for (std::size_t m = 0; m < modes; ++m) {
    warpPoses[m] = spec.fieldPoses[m] == FieldPoses::Exact ? fieldPoses : predictedFieldPoses(flight, ticks, spec.host);
    for (std::size_t k = 0; k < ticks.size(); ++k) {
      const PoseError e = poseError(fieldPoses[k], warpPoses[m][k]);
      meanPoseErrors[m].positionM += e.positionM / static_cast<double>(ticks.size());
      meanPoseErrors[m].angleDeg += e.angleDeg / static_cast<double>(ticks.size());
      maxPoseErrors[m].positionM = std::max(maxPoseErrors[m].positionM, e.positionM);
      maxPoseErrors[m].angleDeg = std::max(maxPoseErrors[m].angleDeg, e.angleDeg);
    }
  }

  std::vector<RateResult> results;
  for (double rateHz : ratesHz) {
    const auto periodNs = static_cast<std::int64_t>(std::llround(1e9 / rateHz));
    const TimePoint firstFrameStart = tFirst - Nanoseconds{periodNs};
    // Per pose mode: its own warps (they keep state from field to field) and accumulators
    std::vector<std::vector<std::unique_ptr<warp::Warp>>> warpsByMode(modes);
    for (auto& warps : warpsByMode)
      for (warp::WarpKind kind : kEvaluatedWarps)
        warps.push_back(warp::makeWarp(kind, spec.rasterWidthPx, spec.rasterHeightPx));
    struct Acc {
      double psnrSum = 0.0, psnrMin = 1e9, violations = 0.0;
      std::uint64_t fallbacks = 0;
      std::vector<double> errors;
      std::vector<double> costsMs;
      std::vector<FieldScore> fields;
      WorstField worst;
      bool keepWorst = false;
    };
    std::vector<std::vector<Acc>> accByMode(modes, std::vector<Acc>(kEvaluatedWarps.size()));
    for (auto& acc : accByMode)
      for (std::size_t w = 0; w < acc.size(); ++w) {
        acc[w].keepWorst = std::find(spec.worstFieldWarps.begin(), spec.worstFieldWarps.end(), kEvaluatedWarps[w]) !=
                           spec.worstFieldWarps.end();
      }
    double ageSumMs = 0.0;
    // One output image per parity, touched before the first timed warp (page faults are not the warp's)
    std::array<Image, 3> outputs;

    Frame current;
    std::int64_t currentIndex = -1;
    for (std::size_t k = 0; k < ticks.size(); ++k) {
      const warp::FieldTick& tick = ticks[k];
      // Newest frame complete by t_k: started at s_j, done one period later
      const std::int64_t j = ((tick.displayTime - firstFrameStart).count() - periodNs) / periodNs;
      if (j != currentIndex) {
        const TimePoint start = firstFrameStart + Nanoseconds{j * periodNs};
        current =
            renderer.render(core::ViewRequest{flight.poseAt(start), start, display, static_cast<std::uint64_t>(j), {}});
        currentIndex = j;
      }
      const double ageMs = toSeconds(tick.displayTime - current.poseTime) * 1e3;
      ageSumMs += ageMs;

      const Pose& pose = fieldPoses[k];
      const TruthField& truth = truths[k];
      const warp::OutputGeometry gTruth =
          warp::OutputGeometry::of(truth.frame, spec.rasterWidthPx, spec.rasterHeightPx);
      const warp::Homography toTruth = warp::rotationHomography(truth.frame, pose, gTruth);
      const warp::OutputGeometry gSource = warp::OutputGeometry::of(current, spec.rasterWidthPx, spec.rasterHeightPx);
      const std::vector<glm::dvec2> checks = checkPixels(spec, tick.parity);
      Image& out = outputs[static_cast<std::size_t>(tick.parity)];
      if (out.empty())
        out.resize(spec.rasterWidthPx, fieldRowCount(tick.parity, spec.rasterHeightPx), current.image.format());
      for (std::size_t m = 0; m < modes; ++m) {
        auto& warps = warpsByMode[m];
        auto& acc = accByMode[m];
        for (std::size_t w = 0; w < warps.size(); ++w) {
          const auto started = std::chrono::steady_clock::now();
          const warp::WarpResult r = warps[w]->warp(current, warpPoses[m][k], tick.parity, out);
          acc[w].costsMs.push_back(
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count());
          if (r.status != warp::WarpStatus::Ok) throw std::runtime_error("warp failed on field " + std::to_string(k));
          const double p = psnrDb(out, truth.pixels);
          acc[w].psnrSum += p;
          acc[w].psnrMin = std::min(acc[w].psnrMin, p);
          acc[w].violations += r.marginViolations;
          acc[w].fallbacks += r.fellBack ? 1 : 0;
          double fieldErrSum = 0.0;
          int fieldErrCount = 0;
          for (const glm::dvec2& c : checks) {
            const auto want = trueSourcePx(truth, pose, gSource, toTruth, current, c);
            const auto got = warps[w]->sourcePx(c);
            if (!want || !got) continue;
            const double e = glm::length(*got - *want);
            acc[w].errors.push_back(e);
            fieldErrSum += e;
            ++fieldErrCount;
          }
          const FieldScore score{ageMs, p, fieldErrCount > 0 ? fieldErrSum / fieldErrCount : 0.0};
          acc[w].fields.push_back(score);
          if (acc[w].keepWorst && (acc[w].worst.field < 0 || p < acc[w].worst.score.psnrDb)) {
            acc[w].worst.field = static_cast<int>(k);
            acc[w].worst.score = score;
            acc[w].worst.truth = truth.pixels;
            acc[w].worst.warped = out;
          }
        }
      }
      step();
    }

    for (std::size_t m = 0; m < modes; ++m) {
      auto& acc = accByMode[m];
      RateResult rr;
      rr.flight = flight.name();
      rr.renderRateHz = rateHz;
      rr.poses = spec.fieldPoses[m];
      rr.meanFrameAgeMs = ageSumMs / static_cast<double>(ticks.size());
      rr.meanPoseError = meanPoseErrors[m];
      rr.maxPoseError = maxPoseErrors[m];
      for (std::size_t w = 0; w < acc.size(); ++w) {
        WarpScore s;
        s.kind = kEvaluatedWarps[w];
        const auto n = static_cast<double>(ticks.size());
        s.meanPsnrDb = acc[w].psnrSum / n;
        s.minPsnrDb = acc[w].psnrMin;
        double sum = 0.0;
        for (double e : acc[w].errors) sum += e;
        s.meanErrPx = acc[w].errors.empty() ? 0.0 : sum / static_cast<double>(acc[w].errors.size());
        s.p95ErrPx = percentile(acc[w].errors, 0.95);
        s.maxErrPx = acc[w].errors.empty() ? 0.0 : *std::max_element(acc[w].errors.begin(), acc[w].errors.end());
        s.violationsPerField = acc[w].violations / n;
        s.fallbacks = acc[w].fallbacks;
        s.medianCostMs = percentile(acc[w].costsMs, 0.5);
        s.fields = std::move(acc[w].fields);
        s.worst = std::move(acc[w].worst);
        rr.warps.push_back(s);
      }
      results.push_back(std::move(rr));
    }
  }
  return results;
}

}  // namespace fieldcast::tools
