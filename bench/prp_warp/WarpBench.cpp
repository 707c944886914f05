// Field warp timings (one core). Run:
//   fieldcast_bench_warp --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// The kernels and the service's field step run at every SIMD level the machine has
// (".../level:avx2"); the others at the best one (FIELDCAST_SIMD's only when they run before
// the per-level ones, which put "auto" back when they end).
// Sizes: an NTSC field (720 × 243 of a 720 × 486 raster) and a 1080i field (1920 × 540).
// The frame is the analytic ground-plane scene (10 % margins, RGB8) rendered once; the field pose
// is 80 ms later with 3° of roll, the kind of map the PRP fits every field.
#include "AnalyticScene.h"

#include <motion/PosePredictor.h>
#include <prp_warp/FieldWarper.h>
#include <prp_warp/Resample.h>
#include <prp_warp/WarpFit.h>
#include <prp_warp/Warps.h>

#include <fieldcast/SimdLevel.h>

#include <benchmark/benchmark.h>
#include <opencv2/imgproc.hpp>

#include <map>
#include <memory>
#include <string>

namespace fieldcast::warp {
namespace {

struct Setup {
  Frame frame;
  Pose fieldPose;
  int rasterW = 0, rasterH = 0;
  QuadraticMap map;
};

/// Raster sizes by benchmark argument: 0 = NTSC 720 × 486, 1 = 1080i 1920 × 1080.
const Setup& setup(int which) {
  static std::map<int, std::unique_ptr<Setup>> cache;
  auto& s = cache[which];
  if (!s) {
    s = std::make_unique<Setup>();
    s->rasterW = which == 0 ? 720 : 1920;
    s->rasterH = which == 0 ? 486 : 1080;
    const Pose framePose{{0.0, 0.0, 300.0}, radians(20.0), radians(-15.0), 0.0};
    s->frame = test::renderFrame(framePose, s->rasterW, s->rasterH, MarginPx{s->rasterW / 10, s->rasterH / 10},
                                 radians(60.0), PixelFormat::Rgb8, 1, true);
    s->fieldPose = framePose;
    s->fieldPose.positionM += glm::dvec3{3.0, 8.0, 1.0};  // 80 ms at ~100 m/s
    s->fieldPose.headingRad += radians(1.0);
    s->fieldPose.rollRad = radians(3.0);
    const QuadraticFit fit =
        fitFieldQuadratic(s->frame, s->fieldPose, OutputGeometry::of(s->frame, s->rasterW, s->rasterH));
    s->map = fit.quadratic;
  }
  return *s;
}

void label(benchmark::State& state, const Setup& s) {
  const int rows = fieldRowCount(FieldParity::Bottom, s.rasterH);
  state.SetLabel(std::to_string(s.rasterW) + "x" + std::to_string(rows) + " field");
  state.counters["Mpx/s"] =
      benchmark::Counter(static_cast<double>(s.rasterW) * rows * static_cast<double>(state.iterations()) / 1e6,
                         benchmark::Counter::kIsRate);
}

/// Runs a benchmark body at one SIMD level, then puts the best level back.
struct AtLevel {
  explicit AtLevel(const std::string& level) { forceSimdLevel(level); }
  ~AtLevel() { forceSimdLevel("auto"); }
  AtLevel(const AtLevel&) = delete;
  AtLevel& operator=(const AtLevel&) = delete;
};

void BM_FastKernel(benchmark::State& state, const std::string& level) {
  const AtLevel at(level);
  const Setup& s = setup(static_cast<int>(state.range(0)));
  Image out(s.rasterW, fieldRowCount(FieldParity::Bottom, s.rasterH), PixelFormat::Rgb8);
  RowScratch scratch(s.rasterW);
  for (auto _ : state) {
    benchmark::DoNotOptimize(resampleQuadraticFast(s.frame.image, s.map, FieldParity::Bottom, s.rasterH, out, scratch));
    benchmark::ClobberMemory();
  }
  label(state, s);
}

/// The depth-mesh resampling alone, through the map the mesh warp solved for the field.
void BM_MeshKernel(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  Image out(s.rasterW, fieldRowCount(FieldParity::Bottom, s.rasterH), PixelFormat::Rgb8);
  MeshWarp mesh(s.rasterW, s.rasterH);
  mesh.warp(s.frame, s.fieldPose, FieldParity::Bottom, out);
  RowScratch scratch(s.rasterW);
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        resampleMeshFast(s.frame.image, mesh.lastMap(), FieldParity::Bottom, s.rasterH, out, scratch));
    benchmark::ClobberMemory();
  }
  label(state, s);
}
BENCHMARK(BM_MeshKernel)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_ScalarReference(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  Image out(s.rasterW, fieldRowCount(FieldParity::Bottom, s.rasterH), PixelFormat::Rgb8);
  for (auto _ : state) {
    benchmark::DoNotOptimize(resampleQuadraticReference(s.frame.image, s.map, FieldParity::Bottom, s.rasterH, out));
    benchmark::ClobberMemory();
  }
  label(state, s);
}
BENCHMARK(BM_ScalarReference)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

/// Evaluates the field's quadratic into OpenCV float maps (pixel-centre origin), as a user of
/// cv::remap would.
void buildRemapMaps(const Setup& s, int rows, cv::Mat& mapX, cv::Mat& mapY) {
  for (int r = 0; r < rows; ++r) {
    float* mx = mapX.ptr<float>(r);
    float* my = mapY.ptr<float>(r);
    const double v = rasterRow(FieldParity::Bottom, r) + 0.5;
    for (int i = 0; i < s.rasterW; ++i) {
      const glm::dvec2 p = s.map({i + 0.5, v});
      mx[i] = static_cast<float>(p.x - 0.5);
      my[i] = static_cast<float>(p.y - 0.5);
    }
  }
}

/// OpenCV's remap with its map built per field, as a user of OpenCV would warp: evaluate the
/// quadratic into float maps (pixel-centre origin), then cv::remap bilinear with edge replicate.
void BM_OpenCvRemapWithMapBuild(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  const int rows = fieldRowCount(FieldParity::Bottom, s.rasterH);
  Image out(s.rasterW, rows, PixelFormat::Rgb8);
  Image& src = const_cast<Image&>(s.frame.image);
  const cv::Mat srcMat(src.heightPx(), src.widthPx(), CV_8UC3, src.row(0));
  cv::Mat dstMat(rows, s.rasterW, CV_8UC3, out.row(0));
  cv::Mat mapX(rows, s.rasterW, CV_32FC1), mapY(rows, s.rasterW, CV_32FC1);
  for (auto _ : state) {
    buildRemapMaps(s, rows, mapX, mapY);
    cv::remap(srcMat, dstMat, mapX, mapY, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    benchmark::ClobberMemory();
  }
  label(state, s);
}
BENCHMARK(BM_OpenCvRemapWithMapBuild)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

/// cv::remap alone with a map built once (what remap costs if the map were free).
void BM_OpenCvRemapOnly(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  const int rows = fieldRowCount(FieldParity::Bottom, s.rasterH);
  Image out(s.rasterW, rows, PixelFormat::Rgb8);
  Image& src = const_cast<Image&>(s.frame.image);
  const cv::Mat srcMat(src.heightPx(), src.widthPx(), CV_8UC3, src.row(0));
  cv::Mat dstMat(rows, s.rasterW, CV_8UC3, out.row(0));
  cv::Mat mapX(rows, s.rasterW, CV_32FC1), mapY(rows, s.rasterW, CV_32FC1);
  buildRemapMaps(s, rows, mapX, mapY);
  for (auto _ : state) {
    cv::remap(srcMat, dstMat, mapX, mapY, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    benchmark::ClobberMemory();
  }
  label(state, s);
}
BENCHMARK(BM_OpenCvRemapOnly)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_QuadraticFit(benchmark::State& state) {
  const Setup& s = setup(0);
  const OutputGeometry g = OutputGeometry::of(s.frame, s.rasterW, s.rasterH);
  Pose pose = s.fieldPose;
  for (auto _ : state) {
    pose.positionM.x += 1e-9;
    benchmark::DoNotOptimize(fitFieldQuadratic(s.frame, pose, g));
  }
}
BENCHMARK(BM_QuadraticFit)->Unit(benchmark::kMicrosecond);

/// Every warp through the common interface (fit + resample), NTSC and 1080i fields.
void BM_Warp(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(1)));
  const auto kind = static_cast<WarpKind>(state.range(0));
  auto warp = makeWarp(kind, s.rasterW, s.rasterH);
  Image out(s.rasterW, fieldRowCount(FieldParity::Bottom, s.rasterH), PixelFormat::Rgb8);
  for (auto _ : state) {
    benchmark::DoNotOptimize(warp->warp(s.frame, s.fieldPose, FieldParity::Bottom, out));
    benchmark::ClobberMemory();
  }
  label(state, s);
  state.SetLabel(std::string(toString(kind)) + " " + std::to_string(s.rasterW) + " wide");
}
BENCHMARK(BM_Warp)
    ->ArgsProduct({{static_cast<int>(WarpKind::Hold), static_cast<int>(WarpKind::Rotation),
                    static_cast<int>(WarpKind::Quadratic), static_cast<int>(WarpKind::Homography),
                    static_cast<int>(WarpKind::Mesh), static_cast<int>(WarpKind::Range3d)},
                   {0, 1}})
    ->Unit(benchmark::kMicrosecond);

/// The whole per-field step of the service: pose, fit, warp, AGC, flicker filter (once per
/// frame), conversion to UYVY. Arguments: 0 = NTSC, 1 = 1080i; then 0 = every field from the same
/// frame (the filter's cost left out), 1 = a new frame every field (a render rate at the field
/// rate: the filter's cost in every field).
void BM_FieldWarperUyvy(benchmark::State& state, const std::string& level) {
  const AtLevel at(level);
  const Setup& s = setup(static_cast<int>(state.range(0)));
  const bool newFrames = state.range(1) != 0;
  Frame frames[2] = {s.frame, s.frame};
  frames[1].frameNumber = s.frame.frameNumber + 1;
  FieldWarperConfig cfg;
  cfg.rasterWidthPx = s.rasterW;
  cfg.rasterHeightPx = s.rasterH;
  cfg.maxFrameWidthPx = s.frame.image.widthPx();
  cfg.maxFrameHeightPx = s.frame.image.heightPx();
  cfg.autoGain.enabled = true;
  cfg.flickerFilter = true;
  FieldWarper warper(cfg);
  Field field = warper.makeField();
  motion::ConstantVelocityPredictor poses;  // the field loop's pose source: its cost stays in the figure
  poses.push(TimePoint{}, s.frame.pose);
  poses.push(TimePoint{Nanoseconds{80'000'000}}, s.fieldPose);
  std::uint64_t k = 0;
  for (auto _ : state) {
    const FieldSpec spec{k, TimePoint{Nanoseconds{80'000'000}}, k % 2 ? FieldParity::Top : FieldParity::Bottom};
    const Frame& frame = frames[newFrames ? k % 2 : 0];
    benchmark::DoNotOptimize(warper.produce(frame, poses.poseAt(spec.displayTime), spec, field));
    ++k;
  }
  label(state, s);
}

/// The per-level benchmarks, one per level this machine runs.
void registerAtEveryLevel() {
  for (const std::string& level : simdLevels()) {
    benchmark::RegisterBenchmark(("BM_FastKernel/level:" + level).c_str(), BM_FastKernel, level)
        ->Arg(0)
        ->Arg(1)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("BM_FieldWarperUyvy/level:" + level).c_str(), BM_FieldWarperUyvy, level)
        ->ArgsProduct({{0, 1}, {0, 1}})
        ->Unit(benchmark::kMicrosecond);
  }
}

}  // namespace
}  // namespace fieldcast::warp

int main(int argc, char** argv) {
  fieldcast::applySimdLevelFromEnvironment();
  fieldcast::warp::registerAtEveryLevel();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
