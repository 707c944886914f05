// Terrain database benchmarks. Run: build/bench/ig_core_terrain/fieldcast_bench_terrain
// The full-size built-in terrain (8192² at 2 m) is built once into $FIELDCAST_CACHE_DIR (default
// cache folder otherwise) by BM_BuiltinBuild/8192 and reused by the other benchmarks.
//
//   BM_BuiltinBuild/<size>/threads:<n>  generate + colour + pyramid + compress + write, seconds;
//                                       threads 1 is the baseline for the parallel speed-up
//   BM_TileLoad / BM_TileDecodeOnly     read+check+decode one 256² tile (page cache warm) vs decode
//                                       from memory: p50/p99 in the counters
//   BM_Flight300                        60 Hz frames flying 300 m/s up the river valley with a
//                                       128 MiB budget (database 682 MiB raw): prefetch hit rate,
//                                       share of renderer samples answered at the level asked
//   BM_HeightQuery/<level>              heightAtM at random points, all tiles resident
#include <ig_core/BuiltinTerrain.h>
#include <ig_core/OpenTerrain.h>
#include <ig_core/TerrainDatabase.h>

#include <fieldcast/Conventions.h>

#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <thread>

namespace {

using namespace fieldcast;
using namespace fieldcast::core;

std::filesystem::path benchCacheDir() { return defaultCacheDir(); }

BuiltinTerrainSpec fullSpec() { return BuiltinTerrainSpec{}; }

// The full-size database, built on first use.
const std::filesystem::path& fullDatabase() {
  static const std::filesystem::path path = ensureBuiltinDatabase(benchCacheDir(), fullSpec());
  return path;
}

// CPU seconds used by every thread of the process so far: on a shared machine the wall time of a
// parallel build depends on the neighbours, its CPU time does not.
double processCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

void BM_BuiltinBuild(benchmark::State& state) {
  BuiltinTerrainSpec spec;
  spec.sizeVox = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  std::filesystem::create_directories(benchCacheDir());
  const std::filesystem::path out = benchCacheDir() / ("bench-" + std::to_string(spec.sizeVox) + ".fctdb");
  BuildReport report;
  const double cpu0 = processCpuSeconds();
  for (auto _ : state) {
    ProceduralColourOptions colour;
    colour.threads = threads;
    const TerrainGrid grid = generateBuiltinTerrain(spec, colour);
    BuildOptions options;
    options.threads = threads;
    report = writeTerrainDatabase(grid, out, options);
  }
  state.counters["cpu_s"] = (processCpuSeconds() - cpu0) / static_cast<double>(state.iterations());
  state.counters["file_MiB"] = static_cast<double>(report.fileBytes) / 1048576.0;
  state.counters["raw_MiB"] = static_cast<double>(report.rawBytes) / 1048576.0;
  state.counters["ratio"] = static_cast<double>(report.rawBytes) / static_cast<double>(report.fileBytes);
  state.counters["Mvox_per_s"] = benchmark::Counter(
      static_cast<double>(spec.sizeVox) * spec.sizeVox / 1e6 * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
  // The full-size build doubles as the cache for the other benchmarks.
  if (spec.sizeVox == 8192 && threads == 0) {
    std::filesystem::rename(out, builtinDatabasePath(benchCacheDir(), fullSpec()));
  } else {
    std::filesystem::remove(out);
  }
}
BENCHMARK(BM_BuiltinBuild)
    ->ArgNames({"size", "threads"})
    ->Args({2048, 1})
    ->Args({2048, 0})
    ->Args({8192, 0})
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

void BM_TileLoad(benchmark::State& state) {
  const DatabaseReader reader(fullDatabase());
  const TerrainGeometry& g = reader.geometry();
  std::mt19937 rng(1);
  TileBuffers tile;
  std::vector<double> us;
  for (auto _ : state) {
    const int tx = static_cast<int>(rng() % static_cast<unsigned>(g.tilesX(0)));
    const int ty = static_cast<int>(rng() % static_cast<unsigned>(g.tilesY(0)));
    const auto t0 = std::chrono::steady_clock::now();
    reader.readTile(0, tx, ty, tile);
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    benchmark::DoNotOptimize(tile.heightQ.data());
  }
  state.counters["p50_us"] = percentile(us, 0.5);
  state.counters["p99_us"] = percentile(us, 0.99);
  state.counters["MiB_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * 0.5, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TileLoad)->Unit(benchmark::kMicrosecond)->Iterations(2000);

// Baseline: the same tiles decoded from memory (no read, no syscalls).
void BM_TileDecodeOnly(benchmark::State& state) {
  const DatabaseReader reader(fullDatabase());
  const TerrainGeometry& g = reader.geometry();
  TileBuffers source;
  reader.readTile(0, 5, 7, source);
  const std::vector<std::byte> compressed = encodeTile(source, g.tileShift, reader.layout().voxelColour, 3);
  TileIndexEntry entry = reader.entry(0, 5, 7);
  entry.compressedBytes = static_cast<std::uint32_t>(compressed.size());
  TileBuffers tile;
  std::vector<double> us;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    decodeTile(compressed, entry, g.tileShift, reader.layout().voxelColour, tile, "bench",
               tileSticks(reader.layout(), reader.sticks().get()));
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  }
  state.counters["p50_us"] = percentile(us, 0.5);
  state.counters["p99_us"] = percentile(us, 0.99);
}
BENCHMARK(BM_TileDecodeOnly)->Unit(benchmark::kMicrosecond)->Iterations(2000);

// Flying 300 m/s up the river from the estuary into the mountains, 200 m above the ground, at
// 60 frames a second in real time, with a 128 MiB budget. Each frame the "renderer" reads the
// ground along 32×24 footprint rays at the level its distance calls for.
void BM_Flight300(benchmark::State& state) {
  std::map<std::string, glm::dvec2> marks;
  for (const BuiltinLandmark& m : builtinLandmarks(fullSpec())) marks[m.name] = m.positionM;
  const glm::dvec2 start = marks["river_mouth"];
  const glm::dvec2 end = marks["valley_head"];
  const double budgetMiB = static_cast<double>(state.range(0));
  TileCacheStats stats;
  double levelHits = 0.0, samples = 0.0;
  for (auto _ : state) {
    TileCacheOptions options;
    const std::unique_ptr<TileCache> terrain =
        openTerrain(fullDatabase().string(), {}, static_cast<std::size_t>(budgetMiB * 1048576.0), fullSpec(), options);
    const Intrinsics camera = Intrinsics::fromHorizontalFov(1024, 768, radians(60.0));
    const double pixelAngle = camera.horizontalFovRad() / camera.widthPx;
    const TerrainGeometry& g = terrain->geometry();
    const glm::dvec2 dir = glm::normalize(end - start);
    const double length = glm::length(end - start);
    const double speed = 300.0;
    const double dt = 1.0 / 60.0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int frame = 0; frame * dt * speed < length; ++frame) {
      const FrameLease lease = terrain->lease();
      const glm::dvec2 p = start + dir * (frame * dt * speed);
      Pose pose;
      pose.positionM = {p.x, p.y, terrain->heightAtM(p.x, p.y, 3) + 200.0};
      pose.headingRad = std::atan2(dir.x, dir.y);
      pose.pitchRad = radians(-8.0);
      terrain->prefetch(pose, glm::dvec3(dir * speed, 0.0), camera);
      // The renderer's reads: ground points along a grid of rays, at the level of their distance.
      for (int b = 0; b < 24; ++b) {
        for (int a = 0; a < 32; ++a) {
          const glm::dvec3 ray = pixelRay(pose, camera, {(a + 0.5) * 32.0, (b + 0.5) * 32.0});
          if (ray.z > -0.01) continue;
          const double t = std::min((pose.positionM.z - 100.0) / -ray.z, 20000.0);
          const glm::dvec3 hit = pose.positionM + t * ray;
          const double voxelsPerPixel = t * pixelAngle / g.spacingM;
          const int level =
              std::clamp(static_cast<int>(std::floor(std::log2(std::max(voxelsPerPixel, 1.0)))), 0, g.levels - 1);
          const double cell = g.spacingM * (1 << level);
          const TerrainView::Sample s =
              terrain->view().sample(level, static_cast<int>(hit.x / cell), static_cast<int>(hit.y / cell));
          samples += 1.0;
          levelHits += s.level == level ? 1.0 : 0.0;
        }
      }
      std::this_thread::sleep_until(t0 + std::chrono::duration<double>((frame + 1) * dt));
    }
    stats = terrain->stats();
  }
  state.counters["prefetch_hit_rate"] = stats.prefetchHitRate;
  state.counters["sample_hit_rate"] = samples > 0 ? levelHits / samples : 0.0;
  state.counters["loads"] = static_cast<double>(stats.loads);
  state.counters["evictions"] = static_cast<double>(stats.evictions);
  state.counters["load_p50_ms"] = stats.loadP50Ms;
  state.counters["load_p99_ms"] = stats.loadP99Ms;
  state.counters["resident_MiB"] = static_cast<double>(stats.residentBytes) / 1048576.0;
}
BENCHMARK(BM_Flight300)
    ->ArgName("budget_MiB")
    ->Arg(128)
    ->Arg(48)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

void BM_HeightQuery(benchmark::State& state) {
  const int level = static_cast<int>(state.range(0));
  static const std::unique_ptr<TileCache> terrain = [] {
    auto t = openTerrain(fullDatabase().string(), {}, std::size_t{1} << 30);
    const TerrainGeometry& g = t->geometry();
    for (int l = 0; l < g.levels; ++l) {
      for (int ty = 0; ty < g.tilesY(l); ++ty) {
        for (int tx = 0; tx < g.tilesX(l); ++tx) t->request(l, tx, ty);
      }
    }
    t->waitIdle(std::chrono::minutes(5));
    return t;
  }();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(0.0, 16380.0);
  std::vector<glm::dvec2> points(4096);
  for (glm::dvec2& p : points) p = {coord(rng), coord(rng)};
  std::size_t k = 0;
  for (auto _ : state) {
    const glm::dvec2& p = points[k++ & 4095];
    benchmark::DoNotOptimize(terrain->heightAtM(p.x, p.y, level));
  }
  state.counters["misses"] = static_cast<double>(terrain->view().missCount());
}
BENCHMARK(BM_HeightQuery)->ArgName("level")->Arg(0)->Arg(3);

}  // namespace

BENCHMARK_MAIN();
