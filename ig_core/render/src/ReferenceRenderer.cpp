// The reference: one ray per pixel, marched in steps of 1/8 voxel of the level of detail at the
// current depth against the bilinear surface of that level (TerrainView::heightAtM), the crossing
// refined by bisection. No coherence, no fixed point, no caching: easy to check by reading. A ray
// that meets no terrain meets the base plane beyond the edge (RENDERER.md) or sees the sky.
#include <ig_core/ReferenceRenderer.h>

#include "ColumnCaster.h"
#include "FrameAssembly.h"
#include "Shading.h"
#include "StickShading.h"

#include <ig_core/VoxelSolid.h>

#include <fieldcast/Conventions.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <tuple>
#include <utility>

#include <glm/geometric.hpp>

namespace fieldcast::core {
namespace {

// Bilinear colour of `level` at level-0 continuous voxel coordinates (x, y).
Rgb bilinearColour(const TerrainView& view, int level, double x, double y) {
  const double fx = std::ldexp(x + 0.5, -level) - 0.5;
  const double fy = std::ldexp(y + 0.5, -level) - 0.5;
  const int i = static_cast<int>(std::floor(fx));
  const int j = static_cast<int>(std::floor(fy));
  const auto tx = static_cast<float>(fx - i);
  const auto ty = static_cast<float>(fy - j);
  const Rgb a = mix(unpackRgb(view.colourRgba(level, i, j)), unpackRgb(view.colourRgba(level, i + 1, j)), tx);
  const Rgb b = mix(unpackRgb(view.colourRgba(level, i, j + 1)), unpackRgb(view.colourRgba(level, i + 1, j + 1)), tx);
  return mix(a, b, ty);
}

// The frame's sun on the terrain colour at level-0 continuous coordinates (x, y): the factors of
// the four voxels of `level` around it (from their slopes, minmod of their neighbours, as the
// caster does), bilinear as the colours are.
float terrainLight(const TerrainView& view, const TerrainLight& light, int level, double x, double y) {
  const TerrainGeometry& g = view.geometry();
  const int w = g.levelWidthVox(level), h = g.levelHeightVox(level);
  const auto height = [&](int a, int b) {
    return static_cast<float>(view.heightQ(level, std::clamp(a, 0, w - 1), std::clamp(b, 0, h - 1)));
  };
  const auto scale = static_cast<float>(g.heightStepM / std::ldexp(g.spacingM, level));
  const auto at = [&](int i, int j) {
    const float here = height(i, j);
    return light.terrain(minmodSlope(here - height(i - 1, j), height(i + 1, j) - here) * scale,
                         minmodSlope(here - height(i, j - 1), height(i, j + 1) - here) * scale);
  };
  const double fx = std::ldexp(x + 0.5, -level) - 0.5;
  const double fy = std::ldexp(y + 0.5, -level) - 0.5;
  const int i = static_cast<int>(std::floor(fx));
  const int j = static_cast<int>(std::floor(fy));
  const auto tx = static_cast<float>(fx - i);
  const auto ty = static_cast<float>(fy - j);
  const float a = at(i, j) + (at(i + 1, j) - at(i, j)) * tx;
  const float b = at(i, j + 1) + (at(i + 1, j + 1) - at(i, j + 1)) * tx;
  return a + (b - a) * ty;
}

// On a stick's side or top (StickShading.h): the texel, at height zM, of the tallest stick among
// the four voxels of `level` around level-0 continuous coordinates (x, y); nothing when none of
// them carries one.
std::optional<std::uint32_t> stickTexelAt(const TerrainView& view, int level, double x, double y, double zM) {
  const StickTable* table = view.sticks();
  if (table == nullptr) return std::nullopt;
  const int i = static_cast<int>(std::floor(std::ldexp(x + 0.5, -level) - 0.5));
  const int j = static_cast<int>(std::floor(std::ldexp(y + 0.5, -level) - 0.5));
  StickVoxel stick;
  for (const auto& [ci, cj] : {std::pair{i, j}, std::pair{i + 1, j}, std::pair{i, j + 1}, std::pair{i + 1, j + 1}}) {
    const TerrainView::Sample v = view.sample(level, ci, cj);
    if (v.stickId != 0) stick = colouringStick(stick, StickVoxel{v.stickId, v.heightQ, v.level});
  }
  if (stick.id == 0) return std::nullopt;
  const TerrainGeometry& g = view.geometry();
  const double zQ = (zM - g.heightBaseM) / g.heightStepM;
  return stickTexel(table->texels(stick.id, stick.level),
                    stickTexelCoordinate(stick, zQ, g.heightStepM / table->unitM()));
}

// A terrain hit's colour (hazed) and range, and the stick texel it lies on (opaque when none);
// `seeThrough`: a level-0 hit on a see-through texel.
struct Shaded {
  Rgb colour;
  float rangeM = std::numeric_limits<float>::infinity();
  std::uint32_t stickRgba = 0xFF000000u;
  double depthM = 0.0;
  bool seeThrough = false;
};

// What the reference sees through a see-through stick texel, by its own plain march apart from
// the caster's column walk (SeeThrough.h has the rules): the ray sampled every 1/32 voxel across
// and 1/16 stick voxel up or down from its hit `front`, each sample in the level-0 column its
// point lies over, taken as a box; a semi-transparent texel blended once as the ray passes it. After two stick-free
// columns, above the surface, the plain march from there (`castFrom(depth)`, a Shaded) — through a see-through texel
// again if it meets one.
template <typename CastFrom>
std::pair<Rgb, float> marchSeeThrough(const TerrainView& view, const Shading& shading, const glm::dvec3& eye,
                                      const glm::dvec3& d, Shaded front, const CastFrom& castFrom) {
  const TerrainGeometry& g = view.geometry();
  const StickTable& table = *view.sticks();
  const double length = glm::length(d);
  const float flat = shading.light().flat();
  SeeThroughLayers layers;
  const auto layer = [&](std::uint32_t rgba, double depth, float alpha) {
    const auto range = static_cast<float>(depth * length);
    layers.add(shading.terrain(Rgb{unpackRgb(rgba).v * flat}, range), alpha, range);
  };
  const auto done = [&](std::uint32_t rgba, double depth) {
    const auto range = static_cast<float>(depth * length);
    return layers.finish(shading.terrain(Rgb{unpackRgb(rgba).v * flat}, range), range);
  };
  const double unitsPerQ = g.heightStepM / table.unitM();
  const double horizontal = std::hypot(d.x, d.y) / g.spacingM;  // voxels per metre of depth
  const double vertical = std::abs(d.z) / table.unitM();        // stick voxels per metre of depth
  const double step = 1.0 / std::max({32.0 * horizontal, 16.0 * vertical, 1e-9});
  const auto columnOf = [&](double depth) {
    const glm::dvec3 p = eye + depth * d;
    return glm::ivec2{static_cast<int>(std::floor((p.x - g.originM.x) / g.spacingM + 0.5)),
                      static_cast<int>(std::floor((p.y - g.originM.y) / g.spacingM + 0.5))};
  };
  const auto inGrid = [&](glm::ivec2 at) { return at.x >= 0 && at.y >= 0 && at.x < g.widthVox && at.y < g.heightVox; };
  const auto heightQAt = [&](double depth) { return (eye.z + depth * d.z - g.heightBaseM) / g.heightStepM; };
  const auto isComplex = [&](const TerrainView::Sample& v) {
    return v.stickId != 0 && table.entry(v.stickId).kind == StickKind::Complex;
  };
  // Column `v` met at height zQ: a plain column's colour, or its stick's texel there
  const auto solidAt = [&](const TerrainView::Sample& v, glm::ivec2 at, double zQ, double depth) {
    if (v.stickId == 0) return done(view.colourRgba(0, at.x, at.y), depth);
    return done(stickTexel(table.texels(v.stickId, 0),
                           stickTexelCoordinate(StickVoxel{v.stickId, v.heightQ, 0}, zQ, unitsPerQ)),
                depth);
  };
  for (int restart = 0; restart < 16 && front.seeThrough; ++restart) {
    const glm::ivec2 start = columnOf(front.depthM);
    // A start over its column's box may fall onto it. One inside it (the hit lies on the surface
    // between voxel centres, which may dip under a box's top) did not enter it and passes through,
    // unless it leaves the column under that surface or, going down, never leaves it: then it is
    // met where it starts.
    const TerrainView::Sample startColumn = inGrid(start) ? view.sample(0, start.x, start.y) : TerrainView::Sample{};
    const double startQ = heightQAt(front.depthM);
    const bool insideStart = inGrid(start) && !isComplex(startColumn) && startQ < startColumn.heightQ;
    bool inStart = true;
    glm::ivec2 last = start;
    int lastTexel = -1, free = 0;
    double depth = front.depthM + 0.5 * step;
    bool handOff = false;
    for (; depth < front.depthM + 1e6; depth += step) {
      const glm::ivec2 at = columnOf(depth);
      const glm::dvec3 p = eye + depth * d;
      const double zQ = heightQAt(depth);
      if (zQ > 65535.0 && d.z > 0.0) {  // above every height, climbing (a ray straight up never leaves its column)
        handOff = true;
        break;
      }
      const bool leaving = inStart && at != start;  // the first sample past the start column
      inStart = inStart && at == start;
      if (insideStart) {
        if (inStart && zQ >= 0.0) continue;  // not its box's hit
        if (inStart || (leaving && p.z < view.heightAtM(p.x, p.y, 0))) {
          return solidAt(startColumn, start, startQ, front.depthM);
        }
      }
      if (!inGrid(at)) {
        handOff = true;
        break;
      }
      const TerrainView::Sample v = view.sample(0, at.x, at.y);
      const bool complex = isComplex(v);
      if (at != last) {
        free = v.stickId == 0 ? free + 1 : 0;
        last = at;
        lastTexel = -1;
      }
      if (!complex) {
        if (zQ < v.heightQ) return solidAt(v, at, zQ, depth);
        if (free >= 2 && p.z > view.heightAtM(p.x, p.y, 0)) {
          handOff = true;
          break;
        }
        continue;
      }
      if (zQ >= v.heightQ) continue;
      const std::span<const std::uint32_t> texels = table.texels(v.stickId, 0);
      const auto k = static_cast<int>(std::floor((v.heightQ - zQ) * unitsPerQ));
      if (k >= static_cast<int>(texels.size())) return done(view.colourRgba(0, at.x, at.y), depth);
      const std::uint32_t texel = texels[static_cast<std::size_t>(k)];
      if (!seeThroughTexel(texel)) return done(texel, depth);
      if (k != lastTexel && (texel >> 24) != 0) layer(texel, depth, static_cast<float>(texel >> 24) / 255.0f);
      lastTexel = k;
    }
    if (!handOff) break;
    front = castFrom(depth);
  }
  return layers.finish(front.colour, front.rangeM);
}

// What the reference sees of an entity along a ray: its own plain march, apart from the entity
// pass's grid walk — the ray sampled every 1/32 voxel through the model's box, the first sample
// in a filled voxel kept, its face the axis whose voxel index changed last.
struct EntitySample {
  double depthM = 0.0;  // along the camera's forward axis (the ray's parameter)
  glm::dvec3 normal{0.0};
  std::uint32_t rgba = 0;
};
std::optional<EntitySample> marchEntity(const EntityInstance& e, const glm::dvec3& eye, const glm::dvec3& ray) {
  if (!e.model || e.model->rgba.empty() || !(e.scale > 0.0)) return std::nullopt;
  const VoxelSolid& m = *e.model;
  const CameraAxes axes = cameraAxes(e.pose);
  const double voxelM = kSolidVoxelM * e.scale;
  // Model coordinates (voxels): x along its right, y its front, z up; its footprint centred on its position.
  const auto local = [&](const glm::dvec3& p) {
    const glm::dvec3 d = p - e.pose.positionM;
    return glm::dvec3{glm::dot(d, axes.right) / voxelM + 0.5 * m.sizeX,
                      glm::dot(d, axes.forward) / voxelM + 0.5 * m.sizeY, glm::dot(d, axes.up) / voxelM};
  };
  const glm::dvec3 o = local(eye);
  const glm::dvec3 d = local(eye + ray) - o;  // per unit of the ray's parameter
  // The parameter range inside the box, by slabs; then samples 1/32 voxel apart along it.
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  const glm::dvec3 size{static_cast<double>(m.sizeX), static_cast<double>(m.sizeY), static_cast<double>(m.sizeZ)};
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < 0.0 || o[a] > size[a]) return std::nullopt;
      continue;
    }
    const double ta = -o[a] / d[a], tb = (size[a] - o[a]) / d[a];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  if (!(t0 < t1)) return std::nullopt;
  const double step = 1.0 / (32.0 * glm::length(d));
  glm::ivec3 before{-1};
  int lastAxis = 2;
  for (double t = t0 + 0.5 * step; t < t1; t += step) {
    const glm::dvec3 p = o + t * d;
    const glm::ivec3 cell{static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y)),
                          static_cast<int>(std::floor(p.z))};
    if (cell.x < 0 || cell.y < 0 || cell.z < 0 || cell.x >= m.sizeX || cell.y >= m.sizeY || cell.z >= m.sizeZ) continue;
    if (before.x >= 0) {
      for (int a = 0; a < 3; ++a)
        if (cell[a] != before[a]) lastAxis = a;
    } else {
      // The first cell: the face of the box the ray entered through.
      const glm::dvec3 entry = o + t0 * d;
      double nearest = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        const double gap = std::min(std::abs(entry[a]), std::abs(entry[a] - size[a]));
        if (gap < nearest) nearest = gap, lastAxis = a;
      }
    }
    before = cell;
    if (!m.filled(cell.x, cell.y, cell.z)) continue;
    const glm::dvec3 axis = lastAxis == 0 ? axes.right : lastAxis == 1 ? axes.forward : axes.up;
    return EntitySample{t, d[lastAxis] > 0.0 ? -axis : axis, m.rgba[m.index(cell.x, cell.y, cell.z)]};
  }
  return std::nullopt;
}

}  // namespace

ReferenceRenderer::ReferenceRenderer(const TerrainView& view)
    : mView(view), mCeilingM(view.geometry().heightM(terrainCeilingQ(view))), mBaseColourRgba(basePlaneColour(view)) {}

ReferenceRenderer::Hit ReferenceRenderer::cast(const ViewGeometry& geo, double u, double v,
                                               double fromDepthM) const noexcept {
  const TerrainGeometry& g = mView.geometry();
  const glm::dvec3 c = geo.pose().positionM;
  const glm::dvec3 d = geo.ray(u, v);
  // Clip the ray (t = depth) to the box over the hull of the level-0 voxel centres, below the ceiling.
  double lo = 0.0;
  double hi = 1e12;
  const auto slab = [&](double origin, double dir, double minV, double maxV) {
    if (std::abs(dir) < 1e-15) return origin >= minV && origin <= maxV;
    const double a = (minV - origin) / dir;
    const double b = (maxV - origin) / dir;
    lo = std::max(lo, std::min(a, b));
    hi = std::min(hi, std::max(a, b));
    return true;
  };
  const double x1 = g.originM.x + (g.widthVox - 1) * g.spacingM;
  const double y1 = g.originM.y + (g.heightVox - 1) * g.spacingM;
  // Seen from outside, the grid's sides end at the base plane (half a height quantum below it, so
  // no terrain hit is clipped); the fast caster clips descending rays alike.
  const double floorM = g.heightBaseM - 0.5 * g.heightStepM;
  if (d.z < 0.0) hi = std::min(hi, (floorM - c.z) / d.z);
  // A ray that meets no terrain meets the base plane beyond the edge, or sees the sky.
  const auto missed = [&]() -> Hit {
    const double rangeM = basePlaneRangeM(c.z - g.heightBaseM, d.z, glm::length(d));
    if (!std::isfinite(rangeM)) return {};
    const double depth = rangeM / glm::length(d);
    return Hit{true, c + depth * d, depth, geo.lodLevel(depth, d), true};
  };
  if (!slab(c.x, d.x, g.originM.x, x1) || !slab(c.y, d.y, g.originM.y, y1) || !slab(c.z, d.z, -1e12, mCeilingM) ||
      lo > hi) {
    return missed();
  }
  const double horizontal = std::sqrt(d.x * d.x + d.y * d.y);
  const auto above = [&](double t, int level) {
    const glm::dvec3 p = c + t * d;
    return p.z - mView.heightAtM(p.x, p.y, level);
  };
  double t = std::max(lo, fromDepthM);
  if (t > hi) return missed();
  int level = geo.lodLevel(t, d);
  double f = above(t, level);
  if (f <= 0.0) {
    const glm::dvec3 p = c + t * d;
    return Hit{true, p, t, level};
  }
  for (int step = 0; step < 50'000'000 && t < hi; ++step) {
    const double voxel = std::ldexp(g.spacingM, level);
    // 1/8 voxel horizontally; steep rays also advance at most 1/8 voxel-height of drop per step.
    const double dt = 0.125 * voxel / std::max(horizontal, 0.05 * std::abs(d.z) + 1e-12);
    const double tNext = std::min(t + dt, hi);
    const int levelNext = geo.lodLevel(tNext, d);
    const double fNext = above(tNext, levelNext);
    if (fNext <= 0.0) {
      // Bisection between the last point above and the first below.
      double a = t;
      double b = tNext;
      for (int k = 0; k < 60 && (b - a) > 1e-7; ++k) {
        const double mid = 0.5 * (a + b);
        if (above(mid, geo.lodLevel(mid, d)) > 0.0) {
          a = mid;
        } else {
          b = mid;
        }
      }
      return Hit{true, c + b * d, b, geo.lodLevel(b, d)};
    }
    t = tNext;
    level = levelNext;
    f = fNext;
  }
  return missed();
}

Frame ReferenceRenderer::render(const ViewRequest& request, const RenderSettings& settings) const {
  Frame frame = frameShell(request, settings, true);
  frame.renderStart = MonotonicClock::now();
  const ViewGeometry geo(frame.pose, frame.intrinsics, mView.geometry(), settings);
  const Shading shading(settings);
  const int s = std::clamp(settings.verticalSupersample, 1, 4);
  const int w = frame.intrinsics.widthPx;
  const auto shade = [&](const Hit& h, const glm::dvec3& d, double length) {
    Shaded out;
    if (!h.hit) {
      out.colour = shading.sky(static_cast<float>(d.z / length));
      return out;
    }
    out.rangeM = static_cast<float>(h.depthM * length);
    out.depthM = h.depthM;
    if (h.basePlane) {
      out.colour = shading.terrain(Rgb{unpackRgb(mBaseColourRgba).v * shading.light().flat()}, out.rangeM);
      return out;
    }
    const TerrainGeometry& g = mView.geometry();
    const double x = (h.pointM.x - g.originM.x) / g.spacingM;
    const double y = (h.pointM.y - g.originM.y) / g.spacingM;
    Rgb colour;
    if (const std::optional<std::uint32_t> stick = stickTexelAt(mView, h.level, x, y, h.pointM.z)) {
      out.stickRgba = *stick;
      out.seeThrough = h.level == 0 && seeThroughTexel(*stick);
      colour = Rgb{unpackRgb(*stick).v * shading.light().flat()};
    } else {
      colour = bilinearColour(mView, h.level, x, y);
      const double blend = settings.blendLevels ? geo.levelBlend(h.depthM * geo.lodStretch(d), h.level) : 0.0;
      if (blend > 0.0) colour = mix(colour, bilinearColour(mView, h.level + 1, x, y), static_cast<float>(blend));
      if (shading.light().relit()) colour.v *= terrainLight(mView, shading.light(), h.level, x, y);
    }
    out.colour = shading.terrain(colour, out.rangeM);
    return out;
  };
  for (int u = 0; u < w; ++u) {
    const RowRun run = frame.footprint.rows(u);
    for (int v = run.first; v < run.end; ++v) {
      Rgb sum;
      float rangePx = std::numeric_limits<float>::infinity();
      for (int sub = s - 1; sub >= 0; --sub) {
        const double vs = v + (sub + 0.5) / s;
        const Hit h = cast(geo, u + 0.5, vs);
        const glm::dvec3 d = geo.ray(u + 0.5, vs);
        const double length = glm::length(d);
        // The terrain (or what a complex stick lets the ray see beyond it), then the nearest
        // entity in front of it, if one is.
        Shaded terrain = shade(h, d, length);
        if (terrain.seeThrough) {
          std::tie(terrain.colour, terrain.rangeM) =
              marchSeeThrough(mView, shading, frame.pose.positionM, d, terrain,
                              [&](double from) { return shade(cast(geo, u + 0.5, vs, from), d, length); });
        }
        std::optional<EntitySample> entity;
        for (const EntityInstance& e : request.entities) {
          const std::optional<EntitySample> seen = marchEntity(e, frame.pose.positionM, d);
          if (seen && seen->depthM * length < terrain.rangeM && (!entity || seen->depthM < entity->depthM))
            entity = seen;
        }
        Rgb colour = terrain.colour;
        float range = terrain.rangeM;
        if (entity) {
          range = static_cast<float>(entity->depthM * length);
          const Rgb lit(unpackRgb(entity->rgba).v * static_cast<float>(shading.light().model(entity->normal)));
          colour = shading.terrain(lit, range);
        }
        if (sub == s / 2 && std::isfinite(range)) rangePx = range;
        sum += colour;
      }
      shading.store(frame.image.row(v), u, sum, 1.0f / static_cast<float>(s));
      frame.rangeM[static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + u] = rangePx;
    }
    repeatColumnEnds(frame, u, run);
  }
  for (ControlPoint& cp : frame.controlPoints) {
    const Hit h = cast(geo, cp.framePx.x, cp.framePx.y);
    setControlPoint(cp, frame, h.hit, h.pointM);
    const glm::dvec3 ray = geo.ray(cp.framePx.x, cp.framePx.y);
    double nearest = h.hit ? h.depthM : std::numeric_limits<double>::infinity();
    for (const EntityInstance& e : request.entities) {
      const std::optional<EntitySample> seen = marchEntity(e, frame.pose.positionM, ray);
      if (seen && seen->depthM < nearest) {
        nearest = seen->depthM;
        setControlPoint(cp, frame, true, frame.pose.positionM + seen->depthM * ray);
      }
    }
  }
  frame.renderEnd = MonotonicClock::now();
  return frame;
}

}  // namespace fieldcast::core
