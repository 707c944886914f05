// Field warp timings (one core). Run:
//   fieldcast_bench_warp --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// The kernels and the service's field step run at every SIMD level the machine has
// (".../level:avx2"); the others at the best one (FIELDCAST_SIMD's only when they run before
// the per-level ones, which put "auto" back when they end).
// Sizes: an NTSC field (720 × 243 of a 720 × 486 raster) and a 1080i field (1920 × 540).
// The frame is the analytic ground-plane scene (10 % margins, RGB8; the ...Grey cases the same in
// Grey8) rendered once; the field pose is 80 ms later with 3° of roll, the kind of map the PRP
// fits every field.
#include "WarpSetup.h"

#include <motion/PosePredictor.h>
#include <prp_warp/FieldWarper.h>
#include <prp_warp/PostProcess.h>
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

void label(benchmark::State& state, const Setup& s) {
  const int rows = fieldRowCount(FieldParity::Bottom, s.rasterH);
  state.SetLabel(std::to_string(s.rasterW) + "x" + std::to_string(rows) + " field");
  state.counters["Mpx/s"] =
      benchmark::Counter(static_cast<double>(s.rasterW) * rows * static_cast<double>(state.iterations()) / 1e6,
                         benchmark::Counter::kIsRate);
}

void BM_FastKernel(benchmark::State& state, const std::string& level, bool grey) {
  const AtLevel at(level);
  const Setup& s = setup(static_cast<int>(state.range(0)));
  const Image& frame = grey ? s.greyFrame.image : s.frame.image;
  Image out(s.rasterW, fieldRowCount(FieldParity::Bottom, s.rasterH), frame.format());
  RowScratch scratch(s.rasterW);
  for (auto _ : state) {
    benchmark::DoNotOptimize(resampleQuadraticFast(frame, s.map, FieldParity::Bottom, s.rasterH, out, scratch));
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

/// OpenCV's remap with its map built per field, as a user of OpenCV would warp: evaluate the
/// quadratic into float maps (pixel-centre origin), then cv::remap bilinear with edge replicate.
void BM_OpenCvRemapWithMapBuild(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  RemapPerField remap(s);
  for (auto _ : state) {
    remap.run(true);
    benchmark::ClobberMemory();
  }
  label(state, s);
}
BENCHMARK(BM_OpenCvRemapWithMapBuild)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

/// cv::remap alone with a map built once (what remap costs if the map were free).
void BM_OpenCvRemapOnly(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  RemapPerField remap(s);
  remap.run(true);
  for (auto _ : state) {
    remap.run(false);
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

/// The whole per-field step of the service: pose, fit, warp of the flicker-filtered frame, AGC,
/// conversion to UYVY (BM_FieldWarperUyvy), or a grey frame to grey fields (BM_FieldWarperGrey).
/// Arguments: 0 = NTSC, 1 = 1080i; then 0 = every field from the same frame, 1 = a new frame every
/// field (a render rate at the field rate). The frames come with their flicker-filtered copies, as
/// the render loop hands them over; making one is BM_FlickerFilterFrame.
void BM_FieldWarper(benchmark::State& state, const std::string& level, bool grey) {
  const AtLevel at(level);
  const Setup& s = setup(static_cast<int>(state.range(0)));
  FieldStep step(s, state.range(1) != 0, grey);
  for (auto _ : state) benchmark::DoNotOptimize(step.run());
  label(state, s);
}

/// The field step (UYVY, a new frame every field) in a banked view: the field rolled by the second
/// argument's degrees, so the map turns the frame by as much (3 is the cases above). First
/// argument: 0 = NTSC, 1 = 1080i.
void BM_FieldWarperBanked(benchmark::State& state, const std::string& level) {
  const AtLevel at(level);
  const Setup& s = setup(static_cast<int>(state.range(0)), static_cast<double>(state.range(1)));
  FieldStep step(s, true);
  for (auto _ : state) benchmark::DoNotOptimize(step.run());
  label(state, s);
}

/// The flicker-filtered copy of a frame (makeFlickerFiltered), made once per frame by the
/// service's render loop before it hands the frame over. Argument: 0 = NTSC frame, 1 = 1080i.
void BM_FlickerFilterFrame(benchmark::State& state, const std::string& level) {
  const AtLevel at(level);
  Frame frame = setup(static_cast<int>(state.range(0))).frame;
  for (auto _ : state) {
    benchmark::DoNotOptimize(makeFlickerFiltered(frame));
    benchmark::ClobberMemory();
  }
  const Image& image = frame.image;
  state.SetLabel(std::to_string(image.widthPx()) + "x" + std::to_string(image.heightPx()) + " frame");
  state.counters["Mpx/s"] = benchmark::Counter(
      static_cast<double>(image.widthPx()) * image.heightPx() * static_cast<double>(state.iterations()) / 1e6,
      benchmark::Counter::kIsRate);
}

/// The AGC's measure of a warped field (every other pixel of every other row, as FieldWarper
/// takes it): in lanes at one level, and the scalar reference.
Image warpedField(const Setup& s) {
  Image field(s.rasterW, fieldRowCount(FieldParity::Bottom, s.rasterH), PixelFormat::Rgb8);
  RowScratch scratch(s.rasterW);
  resampleQuadraticFast(s.frame.image, s.map, FieldParity::Bottom, s.rasterH, field, scratch);
  return field;
}

void BM_MeanLuma(benchmark::State& state, const std::string& level) {
  const AtLevel at(level);
  const Setup& s = setup(static_cast<int>(state.range(0)));
  const Image field = warpedField(s);
  for (auto _ : state) benchmark::DoNotOptimize(meanLuma(field, 2));
  label(state, s);
}

void BM_MeanLumaReference(benchmark::State& state) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  const Image field = warpedField(s);
  for (auto _ : state) benchmark::DoNotOptimize(meanLumaReference(field, 2));
  label(state, s);
}
BENCHMARK(BM_MeanLumaReference)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

/// The per-level benchmarks, one per level this machine runs.
void registerAtEveryLevel() {
  for (const std::string& level : simdLevels()) {
    benchmark::RegisterBenchmark(("BM_FastKernel/level:" + level).c_str(), BM_FastKernel, level, false)
        ->Arg(0)
        ->Arg(1)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("BM_FastKernelGrey/level:" + level).c_str(), BM_FastKernel, level, true)
        ->Arg(0)
        ->Arg(1)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("BM_FlickerFilterFrame/level:" + level).c_str(), BM_FlickerFilterFrame, level)
        ->Arg(0)
        ->Arg(1)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("BM_MeanLuma/level:" + level).c_str(), BM_MeanLuma, level)
        ->Arg(0)
        ->Arg(1)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("BM_FieldWarperUyvy/level:" + level).c_str(), BM_FieldWarper, level, false)
        ->ArgsProduct({{0, 1}, {0, 1}})
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("BM_FieldWarperGrey/level:" + level).c_str(), BM_FieldWarper, level, true)
        ->ArgsProduct({{0, 1}, {0, 1}})
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("BM_FieldWarperBanked/level:" + level).c_str(), BM_FieldWarperBanked, level)
        ->ArgsProduct({{0, 1}, {3, 6, 10, 30, 60}})
        ->Unit(benchmark::kMicrosecond);
  }
}

}  // namespace
}  // namespace fieldcast::warp

int main(int argc, char** argv) {
  fieldcast::applySimdLevelFromEnvironment();
  // One core for OpenCV too, as for the warp: by default its remap splits rows over every core
  // (0.65 against 0.85 ms for an NTSC field on this machine's two)
  cv::setNumThreads(1);
  fieldcast::warp::registerAtEveryLevel();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
