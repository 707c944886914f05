// Cost of one host frame on the IG's link thread (issue 19: decode + apply of a typical host
// message ≤ 20 µs): the datagram IG Control + Entity Control (the ownship) + Rate Control +
// HAT/HOT Request + LOS Segment Request is decoded, applied by HostSession (a HostMotion sample,
// a height from the full-resolution surface, a line-of-sight march of 400 m), and the next
// field's Start of Frame with both answers is built. Time per iteration = one host frame.
// A built-in terrain of 2048² voxels (4 km square, 4 pyramid levels), the full-resolution
// tiles resident. Arguments: 0 no requests; 1 the HAT/HOT request; 3 and a LOS segment down to
// the ground 400 m ahead (a hit); 7 and a LOS segment of 2 km level 20 m above the highest hill
// (no hit: the whole segment searched, the max mip skipping the empty space).
#include "HostSession.h"

#include <ig_core/Georeference.h>
#include <ig_core/OpenTerrain.h>
#include <io_bridge/cigi/DatagramDecoder.h>
#include <io_bridge/cigi/MessageBuilder.h>
#include <motion/HostMotion.h>

#include <benchmark/benchmark.h>

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace {

namespace cigi = fieldcast::io::cigi;
namespace core = fieldcast::core;
using namespace std::chrono_literals;

// The built-in terrain in a directory of its own, level 0 resident; removed at exit.
class Terrain {
 public:
  Terrain() : mDir(std::filesystem::temp_directory_path() / ("fieldcast-bench-host-" + std::to_string(::getpid()))) {
    core::TerrainConfig config;
    config.cacheDir = mDir;
    config.builtin.sizeVox = 2048;
    config.memoryBudgetBytes = std::size_t{256} << 20;
    tiles = core::openTerrain(config);
    const core::TerrainGeometry& g = tiles->geometry();
    for (int ty = 0; ty < g.tilesY(0); ++ty) {
      for (int tx = 0; tx < g.tilesX(0); ++tx) tiles->request(0, tx, ty, -1.0);
    }
    tiles->waitIdle(30s);
  }
  ~Terrain() { std::filesystem::remove_all(mDir); }
  std::shared_ptr<core::TileCache> tiles;

 private:
  std::filesystem::path mDir;
};

void BM_HostFrameDecodeApplyAnswer(benchmark::State& state) {
  static Terrain terrain;
  const auto georeference = std::make_shared<const core::Georeference>(core::Georeference::tangentPlane());
  fieldcast::VirtualClock clock{fieldcast::TimePoint{10s}};
  fieldcast::motion::HostMotion ownship;
  fieldcast::app::HostSession session(ownship, *terrain.tiles, georeference, 1, clock);

  const core::TerrainView& view = terrain.tiles->view();
  const core::TerrainGeometry& g = view.geometry();
  double highestM = 0.0;
  for (int j = 0; j < g.levelHeightVox(g.levels - 1); ++j) {
    for (int i = 0; i < g.levelWidthVox(g.levels - 1); ++i) {
      highestM = std::max(highestM, g.heightM(view.maxHeightQ(g.levels - 1, i, j)));
    }
  }
  const bool level = (state.range(0) & 4) != 0;
  const glm::dvec3 groundM{1000.0, 900.0, 0.0};
  const glm::dvec3 ownshipM = level ? glm::dvec3{1000.0, 900.0, highestM + 20.0}
                                    : glm::dvec3{1000.0, 900.0, view.heightAtM(1000.0, 900.0, 0) + 300.0};
  const glm::dvec3 aheadM = level ? ownshipM + glm::dvec3{0.0, 2000.0, 0.0}
                                  : glm::dvec3{1000.0, 1300.0, view.heightAtM(1000.0, 1300.0, 0) - 5.0};
  const auto geo = georeference->toGeodetic(ownshipM);
  const auto ahead = georeference->toGeodetic(aheadM);
  const auto below = georeference->toGeodetic(groundM);
  cigi::IgControl control;
  control.timestampValid = true;
  control.extrapolationEnabled = true;
  cigi::EntityControl entity;
  entity.latitudeDegOrXM = geo->latitudeDeg;
  entity.longitudeDegOrYM = geo->longitudeDeg;
  entity.altitudeMOrZM = geo->altitudeM;
  entity.extrapolationEnabled = true;
  cigi::RateControl rates;
  rates.xRateMps = 60.0f;
  cigi::HatHotRequest height;
  height.requestType = cigi::HatHotRequestType::Extended;
  height.latitudeDegOrXM = below->latitudeDeg;
  height.longitudeDegOrYM = below->longitudeDeg;
  cigi::LosSegmentRequest los;
  los.sourceLatitudeDegOrXM = geo->latitudeDeg;
  los.sourceLongitudeDegOrYM = geo->longitudeDeg;
  los.sourceAltitudeMOrZM = geo->altitudeM;
  los.destinationLatitudeDegOrXM = ahead->latitudeDeg;
  los.destinationLongitudeDegOrYM = ahead->longitudeDeg;
  los.destinationAltitudeMOrZM = ahead->altitudeM;

  cigi::HostMessageBuilder message;
  cigi::HostDatagramDecoder decoder;
  std::vector<cigi::HostPacket> packets;
  cigi::IgMessageBuilder out;
  std::uint64_t field = 0;
  for (auto _ : state) {
    clock.advance(16'667us);  // one host frame at 60 Hz, and one field
    control.hostFrameNumber = static_cast<std::uint32_t>(field);
    control.timestampTicks = static_cast<std::uint32_t>(field * 1667);
    height.hatHotId = los.losId = static_cast<std::uint16_t>(field);
    message.start(control);
    message.add(entity);
    message.add(rates);
    if (state.range(0) & 1) message.add(height);
    if (state.range(0) & 2) message.add(los);
    if (!decoder.decode(message.bytes(), packets)) state.SkipWithError("datagram not accepted");
    session.onMessage(fieldcast::io::HostMessage{packets, clock.now(), false});
    session.onField(fieldcast::io::FieldAnnouncement{field++, clock.now() + 16ms}, out);
    benchmark::DoNotOptimize(out.bytes().data());
  }
  const fieldcast::app::HostSessionFigures figures = session.figures();
  const bool withHeight = (state.range(0) & 1) != 0, withLos = (state.range(0) & 2) != 0;
  if (figures.ownshipUpdates != field || (withHeight && figures.hatHotAnswered != field) ||
      (withLos && figures.losRequests != field)) {
    state.SkipWithError("not every frame was applied and answered");
  }
  state.SetLabel(std::string("IG Control + Entity + Rate") + (withHeight ? " + HAT/HOT" : "") +
                 (withLos ? (level ? " + LOS 2 km level" : " + LOS to the ground") : ""));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_HostFrameDecodeApplyAnswer)->Arg(0)->Arg(1)->Arg(3)->Arg(7);

}  // namespace

BENCHMARK_MAIN();
