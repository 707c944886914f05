// Frame time of the column caster on a fixed set of poses (including looking at the horizon), at
// NTSC 720×486 and 1920×1080 display sizes with the default 10% margins, on 1 and 2 threads, with
// the plain reference renderer timed on the same poses in the same run for the speed-up.
//
//   fieldcast_bench_render [--terrain=builtin|synthetic] [--cache-dir=DIR] [benchmark flags]
//
// The built-in terrain (8192² voxels at 2 m) is generated into the cache folder on first use;
// --terrain=synthetic uses the procedural test hills (4096² at 2 m) instead.
//
// render_held: the same poses at 720×486 on 2 threads with the frame-time controller holding
// 4 or 6 ms (the grazing-angle rule first, then the quality knob, as the service does): the
// frame time it holds, the knob it settles on and the share of frames with the grazing rule on.
//
// render_objects: the four poses over a wood and over a village of the built-in terrain, the
// furnished terrain against the same land bare (spec.objects = false), frames alternated in one
// run, 720×486 on 2 threads: objects_ms, bare_ms (medians) and their ratio, the secondary rays
// one furnished frame cast through complex sticks, both frames' height samples per pixel, and the
// furnished frame's rays per pixel (above 1 where the look past crossings casts rows again).
//
// render_entities: the four poses over the village with ten vans (config/models/van.vox) on the
// ground in view, against the same frames without them, alternated: entities_ms, without_ms, ratio.
//
// render_sun: the same four poses over the village lit by an evening sun (every colour relit)
// against the colours' own sun (drawn as stored), alternated: relit_ms, stored_ms, ratio.
//
// Counters: frame_ms (per frame), ns_per_px (frame time / frame pixels), steps_per_px (height
// samples per pixel), ref_ns_per_px (reference renderer, one thread, sampled pixels), speedup
// (reference ns/px over this run's ns/px × threads: the per-core speed-up).
#include "BenchPoses.h"

#include <ig_core/BuiltinTerrain.h>
#include <ig_core/FrameTimeController.h>
#include <ig_core/OpenTerrain.h>
#include <ig_core/ReferenceRenderer.h>
#include <ig_core/Renderer.h>
#include <ig_core/SyntheticTerrain.h>
#include <ig_core/ViewGeometry.h>
#include <ig_core/VoxFile.h>

#include <fieldcast/Conventions.h>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace fieldcast::core {
namespace {

struct BenchTerrain {
  std::unique_ptr<MemoryTerrain> synthetic;
  std::unique_ptr<TileCache> cache;
  const TerrainView& view() const { return cache ? cache->view() : synthetic->view(); }
  const TerrainGeometry& geometry() const { return view().geometry(); }
};
std::string gTerrainChoice = "builtin";
std::string gCacheDir;

const BenchTerrain& terrain() {
  static const std::unique_ptr<BenchTerrain> t = [] {
    auto b = std::make_unique<BenchTerrain>();
    if (gTerrainChoice == "synthetic") {
      b->synthetic = makeSyntheticTerrain({SyntheticKind::Hills, 4096, 2.0, 8, 11});
    } else {
      b->cache = openTerrain(gTerrainChoice, gCacheDir, std::size_t{3} << 30);
    }
    return b;
  }();
  return *t;
}

ViewRequest requestFor(int pose, int size) { return benchRequest(terrain().view(), pose, size); }

// Reference renderer ns per pixel for a pose, on a sparse grid of pixels (it is slow).
double referenceNsPerPixel(int pose, int size) {
  static std::map<std::pair<int, int>, double> cache;
  const auto key = std::make_pair(pose, size);
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  const ViewRequest r = requestFor(pose, size);
  const RenderSettings settings;
  const FrameLayout layout = layoutFrame(r.display, settings.marginFraction, 0.0);
  const ViewGeometry geo(r.pose, layout.frame, terrain().geometry(), settings);
  const ReferenceRenderer reference(terrain().view());
  const int step = 24;
  int count = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int v = step / 2; v < layout.frame.heightPx; v += step) {
    for (int u = step / 2; u < layout.frame.widthPx; u += step) {
      benchmark::DoNotOptimize(reference.cast(geo, u + 0.5, v + 0.5));
      ++count;
    }
  }
  const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
  return cache[key] = ns / count;
}

// Pages in everything a view needs at the levels of detail `lod`, and holds it: the figures are
// of rendering, not of loading.
FrameLease pageIn(const ViewRequest& request, const PrefetchLod& lod) {
  if (!terrain().cache) return {};
  const FrameLayout layout = layoutFrame(request.display, 0.1, 0.0);
  terrain().cache->prefetch(request.pose, glm::dvec3{0.0}, layout.frame, lod);
  terrain().cache->waitIdle(std::chrono::seconds(120));
  return terrain().cache->lease();
}

void BM_Render(benchmark::State& state) {
  const int pose = static_cast<int>(state.range(0));
  const int size = static_cast<int>(state.range(1));
  const int threads = static_cast<int>(state.range(2));
  RenderSettings settings;
  settings.maxAnisotropy = static_cast<double>(state.range(3));  // the grazing-angle rule, 0 = off
  settings.laneMarch = state.range(4) != 0;                      // neighbouring columns in step
  state.SetLabel(std::string(kPoses[static_cast<std::size_t>(pose)].name));
  const double refNs = referenceNsPerPixel(pose, size);  // the reference with the rule off
  Renderer renderer(terrain().view(), settings, threads);
  const ViewRequest request = requestFor(pose, size);
  const FrameLease lease = pageIn(request, prefetchLod(settings));
  RenderStats stats;
  Frame frame = renderer.render(request, &stats);  // warm up
  std::vector<double> seconds;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    frame = renderer.render(request, &stats, std::move(frame));
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    benchmark::DoNotOptimize(frame.image.bytes().data());
  }
  std::sort(seconds.begin(), seconds.end());
  const double median = seconds[seconds.size() / 2];
  const double px = static_cast<double>(stats.pixels);
  state.counters["frame_ms"] = 1e3 * median;
  state.counters["ns_per_px"] = 1e9 * median / px;
  state.counters["steps_per_px"] = static_cast<double>(stats.steps) / px;
  state.counters["rays_per_px"] = static_cast<double>(stats.rays) / px;
  state.counters["ref_ns_per_px"] = refNs;
  state.counters["speedup"] = refNs / (1e9 * median * threads / px);
}

// The frame-time controller on one pose: it settles over the warm-up frames, then every
// iteration renders a frame and feeds its time back. (Frames one at a time: the service keeps two
// in flight, which the controller's other update() handles.)
void BM_RenderHeld(benchmark::State& state) {
  const int pose = static_cast<int>(state.range(0));
  const auto targetMs = static_cast<double>(state.range(1));
  state.SetLabel(std::string(kPoses[static_cast<std::size_t>(pose)].name));
  FrameTimeControllerConfig config;
  config.target = fromSeconds(targetMs * 1e-3);
  config.grazingAnisotropy = 2.0;  // the service's default controller_anisotropy
  FrameTimeController controller(config);
  Renderer renderer(terrain().view(), RenderSettings{}, 2);
  const ViewRequest request = requestFor(pose, 0);
  // The knob goes where the controller takes it: paged in for its finest (a coarser knob reads
  // nothing more)
  const FrameLease lease = pageIn(request, PrefetchLod{config.minQuality, 1.0});
  Frame frame;
  const auto renderOnce = [&] {
    const auto start = std::chrono::steady_clock::now();
    frame = renderer.render(request, nullptr, std::move(frame));
    const auto took = std::chrono::steady_clock::now() - start;
    renderer.setQuality(controller.update(std::chrono::duration_cast<Nanoseconds>(took)));
    renderer.setMaxAnisotropy(controller.maxAnisotropy());
    return std::chrono::duration<double>(took).count();
  };
  for (int i = 0; i < 150; ++i) renderOnce();  // settle
  std::vector<double> seconds, quality;
  int grazing = 0;
  for (auto _ : state) {
    quality.push_back(renderer.settings().quality);
    grazing += renderer.settings().maxAnisotropy > 0.0 ? 1 : 0;
    seconds.push_back(renderOnce());
    benchmark::DoNotOptimize(frame.image.bytes().data());
  }
  std::sort(seconds.begin(), seconds.end());
  std::sort(quality.begin(), quality.end());
  state.counters["frame_ms"] = 1e3 * seconds[seconds.size() / 2];
  state.counters["target_ms"] = targetMs;
  state.counters["quality"] = quality[quality.size() / 2];
  state.counters["grazing_share"] = static_cast<double>(grazing) / static_cast<double>(seconds.size());
}

// ---- Objects --------------------------------------------------------------------------------------

// Where the built-in terrain's objects are (generator version 4, seed 1): a wood in the foothills
// and the village on the river's west bank at y 4.45 km
struct ObjectArea {
  const char* name;
  double xM, yM;
};
constexpr std::array<ObjectArea, 2> kObjectAreas{{{"wood", 5000.0, 9300.0}, {"village", 9280.0, 4470.0}}};

// The built-in terrain furnished (objects) or bare, opened once each
TileCache& builtinCache(bool objects) {
  static std::map<bool, std::unique_ptr<TileCache>> caches;
  auto& cache = caches[objects];
  if (!cache) {
    BuiltinTerrainSpec spec;
    spec.objects = objects;
    cache = openTerrain("builtin", gCacheDir, std::size_t{3} << 29, spec);
  }
  return *cache;
}

// A 720×486 view from pose `p` over `area`, at its height above the bare ground (so the camera is
// never inside an object), with every tile it needs paged into `caches`
ViewRequest areaRequest(const BenchPose& p, const ObjectArea& area, std::initializer_list<TileCache*> caches) {
  ViewRequest request;
  request.pose.positionM = {area.xM, area.yM, builtinCache(false).heightAtM(area.xM, area.yM) + p.altitudeM};
  request.pose.headingRad = radians(p.headingDeg);
  request.pose.pitchRad = radians(p.pitchDeg);
  request.display = Intrinsics::fromHorizontalFov(720, 486, radians(60.0));
  const FrameLayout layout = layoutFrame(request.display, 0.1, 0.0);
  for (TileCache* cache : caches) {
    cache->prefetch(request.pose, glm::dvec3{0.0}, layout.frame);
    cache->waitIdle(std::chrono::seconds(120));
  }
  return request;
}

// Renders with `first` and `second` alternately, one frame each per benchmark iteration (so both
// see the same machine load); their median frame times in ms.
template <class First, class Second>
std::pair<double, double> alternatedMedianMs(benchmark::State& state, First&& first, Second&& second) {
  std::vector<double> firstS, secondS;
  const auto timed = [](auto& render) {
    const auto start = std::chrono::steady_clock::now();
    render();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  for (auto _ : state) {
    firstS.push_back(timed(first));
    secondS.push_back(timed(second));
  }
  std::sort(firstS.begin(), firstS.end());
  std::sort(secondS.begin(), secondS.end());
  return {1e3 * firstS[firstS.size() / 2], 1e3 * secondS[secondS.size() / 2]};
}

// One more frame of `request` into `frame` (its buffers reused).
void renderInto(Renderer& renderer, const ViewRequest& request, Frame& frame) {
  frame = renderer.render(request, nullptr, std::move(frame));
  benchmark::DoNotOptimize(frame.image.bytes().data());
}

void BM_RenderObjects(benchmark::State& state) {
  const BenchPose& p = kPoses[static_cast<std::size_t>(state.range(0))];
  const ObjectArea& area = kObjectAreas[static_cast<std::size_t>(state.range(1))];
  state.SetLabel(std::string(area.name) + " " + p.name);
  TileCache& furnished = builtinCache(true);
  TileCache& bare = builtinCache(false);
  const ViewRequest request = areaRequest(p, area, {&furnished, &bare});
  const FrameLease leaseFurnished = furnished.lease(), leaseBare = bare.lease();
  Renderer withObjects(furnished.view(), RenderSettings{}, 2), without(bare.view(), RenderSettings{}, 2);
  RenderStats stats;
  RenderStats bareStats;
  Frame a = withObjects.render(request, &stats), b = without.render(request, &bareStats);  // warm up
  const auto [objectsMs, bareMs] = alternatedMedianMs(
      state, [&] { renderInto(withObjects, request, a); }, [&] { renderInto(without, request, b); });
  state.counters["secondary_rays"] = static_cast<double>(stats.secondaryRays);  // through complex sticks
  state.counters["objects_ms"] = objectsMs;
  state.counters["bare_ms"] = bareMs;
  state.counters["ratio"] = objectsMs / bareMs;
  // Height samples per pixel: the objects' share of the extra work is the march's
  state.counters["steps_per_px"] = static_cast<double>(stats.steps) / static_cast<double>(stats.pixels);
  state.counters["bare_steps_per_px"] = static_cast<double>(bareStats.steps) / static_cast<double>(bareStats.pixels);
  // Rays per pixel: above 1 where rows are cast again ray by ray (the look past crossings)
  state.counters["rays_per_px"] = static_cast<double>(stats.rays) / static_cast<double>(stats.pixels);
}

// ---- Entities -------------------------------------------------------------------------------------

// Ten vans (config/models/van.vox) on the ground the view sees, over the village of the built-in
// terrain: frames with them and without them alternated, 720×486 on 2 threads
void BM_RenderEntities(benchmark::State& state) {
  const BenchPose& p = kPoses[static_cast<std::size_t>(state.range(0))];
  const ObjectArea& area = kObjectAreas[1];
  state.SetLabel(std::string(area.name) + " " + p.name);
  TileCache& cache = builtinCache(true);
  const ViewRequest request = areaRequest(p, area, {&cache});
  const FrameLayout layout = layoutFrame(request.display, 0.1, 0.0);
  const FrameLease lease = cache.lease();
  RenderSettings settings;
  settings.rangeImage = true;  // both frames have it: the comparison is of the entity pass alone
  Renderer renderer(cache.view(), settings, 2);
  Frame bare = renderer.render(request);
  // A 5 × 2 grid of pixels over the display's lower half: a van where each meets the ground
  const auto van = std::make_shared<const VoxelSolid>(readVoxFile(FIELDCAST_SOURCE_DIR "/config/models/van.vox"));
  ViewRequest withVans = request;
  for (int k = 0; k < 10; ++k) {
    const glm::dvec2 px{layout.margin.x + (0.1 + 0.2 * (k % 5)) * request.display.widthPx,
                        layout.margin.y + (k < 5 ? 0.6 : 0.85) * request.display.heightPx};
    const float range = bare.rangeM[static_cast<std::size_t>(px.y) * static_cast<std::size_t>(bare.intrinsics.widthPx) +
                                    static_cast<std::size_t>(px.x)];
    if (!std::isfinite(range)) continue;
    EntityInstance e;
    e.id = static_cast<std::uint32_t>(k + 1);
    e.model = van;
    e.pose.positionM = request.pose.positionM + static_cast<double>(range) * pixelRay(bare.pose, bare.intrinsics, px);
    e.pose.headingRad = radians(37.0 * k);
    withVans.entities.push_back(e);
  }
  Frame with = renderer.render(withVans);  // warm up
  const auto [withMs, withoutMs] = alternatedMedianMs(
      state, [&] { renderInto(renderer, withVans, with); }, [&] { renderInto(renderer, request, bare); });
  state.counters["entities"] = static_cast<double>(withVans.entities.size());
  state.counters["entities_ms"] = withMs;
  state.counters["without_ms"] = withoutMs;
  state.counters["ratio"] = withMs / withoutMs;
}

// ---- The sun ---------------------------------------------------------------------------------------

// The four poses over the village, lit by an evening sun (west-south-west, 15° up: every terrain
// colour relit) against the colours' own sun (drawn as stored), alternated, 720×486 on 2 threads.
void BM_RenderSun(benchmark::State& state) {
  const BenchPose& p = kPoses[static_cast<std::size_t>(state.range(0))];
  const ObjectArea& area = kObjectAreas[1];
  state.SetLabel(std::string(area.name) + " " + p.name);
  TileCache& cache = builtinCache(true);
  const ViewRequest request = areaRequest(p, area, {&cache});
  const FrameLease lease = cache.lease();
  RenderSettings evening;
  evening.sun = {250.0, 15.0};
  Renderer relit(cache.view(), evening, 2), stored(cache.view(), RenderSettings{}, 2);
  Frame a = relit.render(request), b = stored.render(request);  // warm up
  const auto [relitMs, storedMs] = alternatedMedianMs(
      state, [&] { renderInto(relit, request, a); }, [&] { renderInto(stored, request, b); });
  state.counters["relit_ms"] = relitMs;
  state.counters["stored_ms"] = storedMs;
  state.counters["ratio"] = relitMs / storedMs;
}

void registerAll() {
  for (int pose = 0; pose < static_cast<int>(kPoses.size()); ++pose) {
    benchmark::RegisterBenchmark("render_sun", BM_RenderSun)
        ->Arg(pose)
        ->ArgName("pose")
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  for (int pose = 0; pose < static_cast<int>(kPoses.size()); ++pose) {
    benchmark::RegisterBenchmark("render_entities", BM_RenderEntities)
        ->Arg(pose)
        ->ArgName("pose")
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  for (int area = 0; area < static_cast<int>(kObjectAreas.size()); ++area) {
    for (int pose = 0; pose < static_cast<int>(kPoses.size()); ++pose) {
      benchmark::RegisterBenchmark("render_objects", BM_RenderObjects)
          ->Args({pose, area})
          ->ArgNames({"pose", "area"})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
  for (int size = 0; size < 2; ++size) {
    for (int anisotropy : {0, 2}) {
      for (int threads : {1, 2}) {
        for (int lanes : {0, 1}) {
          for (int pose = 0; pose < static_cast<int>(kPoses.size()); ++pose) {
            benchmark::RegisterBenchmark("render", BM_Render)
                ->Args({pose, size, threads, anisotropy, lanes})
                ->ArgNames({"pose", "size", "threads", "anisotropy", "lanes"})
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
          }
        }
      }
    }
  }
  for (int targetMs : {4, 6}) {
    for (int pose = 0; pose < static_cast<int>(kPoses.size()); ++pose) {
      benchmark::RegisterBenchmark("render_held", BM_RenderHeld)
          ->Args({pose, targetMs})
          ->ArgNames({"pose", "target_ms"})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
}

}  // namespace
}  // namespace fieldcast::core

int main(int argc, char** argv) {
  // Our own flags first; the rest goes to Google Benchmark.
  int kept = 1;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg.rfind("--terrain=", 0) == 0) {
      fieldcast::core::gTerrainChoice = arg.substr(10);
    } else if (arg.rfind("--cache-dir=", 0) == 0) {
      fieldcast::core::gCacheDir = arg.substr(12);
    } else {
      argv[kept++] = argv[a];
    }
  }
  argc = kept;
  benchmark::Initialize(&argc, argv);
  fieldcast::core::registerAll();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
