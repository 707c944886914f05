#pragma once
// The warp-fidelity evaluation of fieldcast-latency: a scripted flight in virtual time; the IG
// renders frames at a fixed rate with one frame period of render latency; every field is made by
// each warp from the newest frame and compared with the ground truth rendered at the field's own
// pose.

#include "EvaluatedFlight.h"
#include "PredictedPoses.h"

#include <prp_warp/Warp.h>

#include <ig_core/Renderer.h>

#include <fieldcast/Field.h>
#include <fieldcast/Time.h>

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace fieldcast::tools {

/// Where each field's pose comes from.
enum class FieldPoses : std::uint8_t {
  Exact,          ///< the flight's own pose at the field's display time: the warps alone are judged
  HostPredicted,  ///< predicted from host samples (HostFeed): prediction and warp together
};

/// Name in tables and files ("exact", "host").
constexpr const char* toString(FieldPoses p) noexcept { return p == FieldPoses::Exact ? "exact" : "host"; }

/// What to evaluate.
struct EvaluationSpec {
  int rasterWidthPx = 360;  ///< output raster = display window rendered by the IG
  int rasterHeightPx = 240;
  double hfovDeg = 60.0;
  RationalRate fieldRate{60000, 1001};
  ScanMode scan = ScanMode::Interlaced;
  FieldOrder order = FieldOrder::BottomFirst;
  double startS = 0.5;    ///< flight time of the first field (frames start one frame period earlier)
  int fields = 240;       ///< fields evaluated per flight and rate
  int checkColumns = 16;  ///< held-out check pixels: a grid over the raster, off the control grid
  int checkRows = 12;
  /// Warps whose worst field (lowest PSNR) is kept with its pictures, for the report's strips.
  std::vector<warp::WarpKind> worstFieldWarps{warp::WarpKind::Quadratic, warp::WarpKind::Mesh};
  /// The field poses evaluated, each against the same frames and truth.
  std::vector<FieldPoses> fieldPoses{FieldPoses::Exact};
  HostFeed host;  ///< for FieldPoses::HostPredicted
};

/// The warps compared, in table order.
inline constexpr std::array<warp::WarpKind, 6> kEvaluatedWarps{warp::WarpKind::Hold,      warp::WarpKind::Rotation,
                                                               warp::WarpKind::Quadratic, warp::WarpKind::Homography,
                                                               warp::WarpKind::Mesh,      warp::WarpKind::Range3d};

/// One field as one warp made it.
struct FieldScore {
  double ageMs = 0.0;      ///< display time − the source frame's pose time
  double psnrDb = 0.0;     ///< against the truth
  double meanErrPx = 0.0;  ///< geometric error at the field's check pixels
};

/// The field a warp did worst on (lowest PSNR), with its pictures (the field's rows only).
struct WorstField {
  int field = -1;  ///< index in the evaluated fields; −1 when not kept
  FieldScore score;
  Image truth;
  Image warped;
};

/// Figures of one warp over one flight at one render rate.
struct WarpScore {
  warp::WarpKind kind = warp::WarpKind::Hold;
  double meanPsnrDb = 0.0;
  double minPsnrDb = 0.0;
  double meanErrPx = 0.0;  ///< geometric error at the check pixels, mean over fields and pixels
  double p95ErrPx = 0.0;
  double maxErrPx = 0.0;
  double violationsPerField = 0.0;  ///< margin violations (output pixels) per field
  std::uint64_t fallbacks = 0;      ///< fields where the warp fell back
  double medianCostMs = 0.0;        ///< the warp's own time per field (one core), median over fields
  std::vector<FieldScore> fields;   ///< every field, in display order
  WorstField worst;                 ///< kept for the warps of EvaluationSpec::worstFieldWarps
};

/// One row group of the table.
struct RateResult {
  std::string flight;
  double renderRateHz = 0.0;
  FieldPoses poses = FieldPoses::Exact;
  double meanFrameAgeMs = 0.0;  ///< display time − frame pose time, mean over fields
  PoseError meanPoseError;      ///< the field poses against the flight's (zero when exact)
  PoseError maxPoseError;
  std::vector<WarpScore> warps;  ///< in kEvaluatedWarps order
};

/// Frames rendered once per field for the ground truth, shared by every rate of one flight.
struct TruthField {
  Frame frame;   ///< rendered at the field's pose (unrolled, with range)
  Image pixels;  ///< the field's rows, roll applied exactly
};

/// Progress of one flight's evaluation: steps done of the total (one per truth field rendered and
/// one per field evaluated at each rate).
using Progress = std::function<void(int done, int total)>;

/// Runs the evaluation of one flight for every rate and every FieldPoses of the spec (results
/// rate-major, poses in the spec's order). Throws std::runtime_error when the flight ends before
/// the requested fields.
std::vector<RateResult> evaluateFlight(const EvaluatedFlight& flight, core::Renderer& renderer,
                                       const EvaluationSpec& spec, const std::vector<double>& ratesHz,
                                       const Progress& progress = {});

/// Minimum height above the terrain (m) along the evaluated part of the flight.
double minimumClearanceM(const EvaluatedFlight& flight, const core::TerrainView& terrain, const EvaluationSpec& spec);

}  // namespace fieldcast::tools
