// Cost of the camera conventions every module calls per control point and per pixel.
#include <fieldcast/Conventions.h>

#include <benchmark/benchmark.h>

namespace fieldcast {
namespace {

void BM_ProjectPoint(benchmark::State& state) {
  const Pose pose{{100.0, 200.0, 500.0}, radians(30.0), radians(-20.0), radians(5.0)};
  const Intrinsics k = Intrinsics::fromHorizontalFov(720, 486, radians(60.0));
  glm::dvec3 p{300.0, 900.0, 10.0};
  for (auto _ : state) {
    p.x += 1e-6;
    benchmark::DoNotOptimize(projectPoint(pose, k, p));
  }
}
BENCHMARK(BM_ProjectPoint);

void BM_PixelRay(benchmark::State& state) {
  const Pose pose{{100.0, 200.0, 500.0}, radians(30.0), radians(-20.0), radians(5.0)};
  const Intrinsics k = Intrinsics::fromHorizontalFov(720, 486, radians(60.0));
  glm::dvec2 px{10.5, 20.5};
  for (auto _ : state) {
    px.x += 1e-6;
    benchmark::DoNotOptimize(pixelRay(pose, k, px));
  }
}
BENCHMARK(BM_PixelRay);

}  // namespace
}  // namespace fieldcast

BENCHMARK_MAIN();
