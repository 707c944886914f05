// Frame assembly around the column caster: layout, buffers, control rays, the pool job.
#include <ig_core/Renderer.h>

#include "ColumnCaster.h"
#include "EntityPass.h"
#include "FrameAssembly.h"

#include <ig_core/ViewGeometry.h>

#include <atomic>

namespace fieldcast::core {

class Renderer::InFlight {
 public:
  InFlight(Renderer& r, const ViewRequest& request, const RenderSettings& s, Frame&& recycle)
      : renderer(r),
        quality(s.quality),
        maxAnisotropy(s.maxAnisotropy),
        entities(request.entities),
        frame(frameShell(request, s, s.rangeImage || !entities.empty(), std::move(recycle))),
        geometry(frame.pose, frame.intrinsics, r.mView->geometry(), s),
        caster(*r.mView, geometry, s, r.mCeilingQ, r.mBaseColourRgba, &frame.image,
               frame.hasRange() ? frame.rangeM.data() : nullptr, &frame.footprint) {
    frame.renderStart = MonotonicClock::now();
    job.run = &InFlight::runColumns;
    job.context = this;
    job.count = frame.intrinsics.widthPx;
    job.chunk = CasterThread::kStagingColumns;
  }

  static void runColumns(void* context, int begin, int end, int worker) noexcept {
    auto* self = static_cast<InFlight*>(context);
    CasterThread& t = self->renderer.mThreads[static_cast<std::size_t>(worker)];
    // Tile pointers are held for one chunk only, so a tile withdrawn between frames is never used.
    t.resetTiles();
    const std::uint64_t steps = t.steps;
    const std::uint64_t rays = t.rays;
    const std::uint64_t secondary = t.secondaryRays;
    castColumns(self->caster, begin, end, t);
    self->steps.fetch_add(t.steps - steps, std::memory_order_relaxed);
    self->rays.fetch_add(t.rays - rays, std::memory_order_relaxed);
    self->secondaryRays.fetch_add(t.secondaryRays - secondary, std::memory_order_relaxed);
  }

  Renderer& renderer;
  double quality;  // the settings that change from frame to frame, for RenderStats
  double maxAnisotropy;
  std::vector<EntityInstance> entities;  // drawn after the columns (they need the range image)
  Frame frame;
  ViewGeometry geometry;
  CasterFrame caster;
  PoolJob job;
  std::atomic<std::uint64_t> steps{0};
  std::atomic<std::uint64_t> rays{0};
  std::atomic<std::uint64_t> secondaryRays{0};
};

Renderer::Renderer(const TerrainView& view, const RenderSettings& settings, int threads)
    : mView(&view),
      mSettings(settings),
      mCeilingQ(terrainCeilingQ(view)),
      mBaseColourRgba(basePlaneColour(view)),
      mThreads(static_cast<std::size_t>(
          threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency())))),
      mCaller(std::make_unique<CasterThread>()),
      mPool(static_cast<int>(mThreads.size())) {}

Renderer::~Renderer() = default;

void Renderer::setTerrain(const TerrainView& view) {
  mView = &view;
  mCeilingQ = terrainCeilingQ(view);
  mBaseColourRgba = basePlaneColour(view);
}

void Renderer::InFlightDeleter::operator()(InFlight* frame) const noexcept {
  frame->renderer.mPool.wait(frame->job);
  delete frame;
}

Frame Renderer::render(const ViewRequest& request, RenderStats* stats, Frame&& recycle) {
  return finish(submit(request, std::move(recycle)), stats);
}

Renderer::Ticket Renderer::submit(const ViewRequest& request, Frame&& recycle) {
  Ticket f(new InFlight(*this, request, mSettings, std::move(recycle)));
  // Control rays: the same march as the pixels, cast from the camera.
  mCaller->resetTiles();
  for (ControlPoint& cp : f->frame.controlPoints) {
    const CastResult hit = castRay(f->caster, cp.framePx.x, cp.framePx.y, *mCaller);
    setControlPoint(cp, f->frame, hit.hit, hit.pointM);
  }
  mPool.submit(f->job);
  return f;
}

Frame Renderer::finish(Ticket f, RenderStats* stats) {
  mPool.wait(f->job);
  if (!f->entities.empty()) drawEntities(f->entities, f->geometry, f->caster.shading, f->frame);
  f->frame.renderEnd = MonotonicClock::now();
  if (stats != nullptr) {
    stats->steps = f->steps.load(std::memory_order_relaxed);
    stats->rays = f->rays.load(std::memory_order_relaxed);
    stats->secondaryRays = f->secondaryRays.load(std::memory_order_relaxed);
    stats->pixels = static_cast<std::uint64_t>(f->frame.intrinsics.widthPx) *
                    static_cast<std::uint64_t>(f->frame.intrinsics.heightPx);
    stats->quality = f->quality;
    stats->maxAnisotropy = f->maxAnisotropy;
  }
  return std::move(f->frame);
}

}  // namespace fieldcast::core
