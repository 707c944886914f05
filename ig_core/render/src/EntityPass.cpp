// The entity pass: each entity's voxel grid ray-cast inside its screen bounding box (grid
// traversal after Amanatides & Woo, "A fast voxel traversal algorithm for ray tracing", 1987),
// composited with the terrain by the frame's range image.
#include "EntityPass.h"

#include "FrameAssembly.h"

#include <fieldcast/Conventions.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace fieldcast::core {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// An entity's axes and scale: world point p is model point ((p − base)·right / s + sizeX/2,
// (p − base)·forward / s + sizeY/2, (p − base)·up / s) in voxels
struct ModelFrame {
  CameraAxes axes;
  glm::dvec3 base;
  double voxelM;
  glm::dvec3 toModel(const glm::dvec3& p, const VoxelSolid& m) const noexcept {
    const glm::dvec3 d = p - base;
    return {glm::dot(d, axes.right) / voxelM + 0.5 * m.sizeX, glm::dot(d, axes.forward) / voxelM + 0.5 * m.sizeY,
            glm::dot(d, axes.up) / voxelM};
  }
  glm::dvec3 directionToModel(const glm::dvec3& d) const noexcept {
    return glm::dvec3(glm::dot(d, axes.right), glm::dot(d, axes.forward), glm::dot(d, axes.up)) / voxelM;
  }
  glm::dvec3 toWorld(const glm::dvec3& local, const VoxelSolid& m) const noexcept {
    return base + (local.x - 0.5 * m.sizeX) * voxelM * axes.right + (local.y - 0.5 * m.sizeY) * voxelM * axes.forward +
           local.z * voxelM * axes.up;
  }
};

ModelFrame modelFrame(const EntityInstance& e) noexcept {
  return {cameraAxes(e.pose), e.pose.positionM, kSolidVoxelM * e.scale};
}

// entityScreenBox, for a model frame already made
PixelBox screenBox(const EntityInstance& e, const ModelFrame& mf, const ViewGeometry& geo) noexcept {
  const VoxelSolid& m = *e.model;
  const Intrinsics& k = geo.intrinsics();
  const CameraAxes& cam = geo.axes();
  const glm::dvec3 eye = geo.pose().positionM;
  // The box's corners in camera coordinates (right, up, forward)
  std::array<glm::dvec3, 8> corners;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 d = mf.toWorld({(c & 1) ? m.sizeX : 0, (c & 2) ? m.sizeY : 0, (c & 4) ? m.sizeZ : 0}, m) - eye;
    corners[static_cast<std::size_t>(c)] = {glm::dot(d, cam.right), glm::dot(d, cam.up), glm::dot(d, cam.forward)};
  }
  // Clipped to the near plane: the corners in front of it, and where the box's edges cross it (a
  // box reaching behind the eye, beside it, covers only the side of the screen it is on).
  constexpr double kNear = 1e-3;
  double uMin = kInf, vMin = kInf, uMax = -kInf, vMax = -kInf;
  const auto add = [&](const glm::dvec3& p) {
    const double u = k.cxPx + k.fxPx * p.x / p.z;
    const double v = k.cyPx - k.fyPx * p.y / p.z;
    uMin = std::min(uMin, u), uMax = std::max(uMax, u), vMin = std::min(vMin, v), vMax = std::max(vMax, v);
  };
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3& a = corners[static_cast<std::size_t>(c)];
    if (a.z > kNear) add(a);
    for (const int axis : {1, 2, 4}) {  // the three edges from this corner to corners with the bit set
      if ((c & axis) != 0) continue;
      const glm::dvec3& b = corners[static_cast<std::size_t>(c | axis)];
      if ((a.z > kNear) == (b.z > kNear)) continue;
      add(a + (b - a) * ((kNear - a.z) / (b.z - a.z)));
    }
  }
  if (!(uMin <= uMax) || !(vMin <= vMax)) return {};  // wholly behind the near plane (or not finite)
  const auto clampU = [&](double u) { return static_cast<int>(std::clamp(u, 0.0, static_cast<double>(k.widthPx))); };
  const auto clampV = [&](double v) { return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(k.heightPx))); };
  return {clampU(std::floor(uMin)), clampV(std::floor(vMin)), clampU(std::ceil(uMax) + 1.0),
          clampV(std::ceil(vMax) + 1.0)};
}

bool castModel(const VoxelSolid& m, const ModelFrame& mf, const glm::dvec3& origin, const glm::dvec3& ray,
               double maxDepthM, EntityHit& hit) noexcept {
  const glm::dvec3 o = mf.toModel(origin, m);
  const glm::dvec3 d = mf.directionToModel(ray);
  const auto finite = [](const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  if (!finite(o) || !finite(d)) return false;  // a pose or scale from outside that is not a place
  const std::array<int, 3> size{m.sizeX, m.sizeY, m.sizeZ};
  // Where the ray is inside the model's box (slabs)
  double tEnter = 0.0, tExit = maxDepthM;
  int enterAxis = -1;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < 0.0 || o[a] >= size[static_cast<std::size_t>(a)]) return false;
      continue;
    }
    double t0 = (0.0 - o[a]) / d[a], t1 = (size[static_cast<std::size_t>(a)] - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > tEnter) tEnter = t0, enterAxis = a;
    tExit = std::min(tExit, t1);
  }
  if (!(tEnter < tExit)) return false;
  // Walk the voxels from the entry, one boundary at a time
  std::array<int, 3> cell{}, step{};
  std::array<double, 3> tNext{}, tDelta{};
  for (int a = 0; a < 3; ++a) {
    const auto A = static_cast<std::size_t>(a);
    cell[A] = std::clamp(static_cast<int>(std::floor(o[a] + d[a] * tEnter)), 0, size[A] - 1);
    step[A] = d[a] > 0.0 ? 1 : -1;
    tDelta[A] = d[a] != 0.0 ? std::abs(1.0 / d[a]) : kInf;
    tNext[A] = d[a] != 0.0 ? (cell[A] + (d[a] > 0.0 ? 1.0 : 0.0) - o[a]) / d[a] : kInf;
  }
  double t = tEnter;
  int axis = enterAxis;
  for (;;) {
    if (m.filled(cell[0], cell[1], cell[2])) {
      hit.depthM = t;
      hit.rgba = m.rgba[m.index(cell[0], cell[1], cell[2])];
      const int a = axis < 0 ? 2 : axis;  // a ray that starts inside: light it as a top
      const glm::dvec3 axisWorld = a == 0 ? mf.axes.right : a == 1 ? mf.axes.forward : mf.axes.up;
      hit.normal = axis < 0 ? mf.axes.up : (d[a] > 0.0 ? -axisWorld : axisWorld);
      return true;
    }
    axis = tNext[0] < tNext[1] ? (tNext[0] < tNext[2] ? 0 : 2) : (tNext[1] < tNext[2] ? 1 : 2);
    const auto A = static_cast<std::size_t>(axis);
    t = tNext[A];
    if (t >= tExit) return false;
    cell[A] += step[A];
    if (cell[A] < 0 || cell[A] >= size[A]) return false;
    tNext[A] += tDelta[A];
  }
}

}  // namespace

PixelBox entityScreenBox(const EntityInstance& entity, const ViewGeometry& geometry) noexcept {
  if (!entity.model || entity.model->rgba.empty() || !(entity.scale > 0.0)) return {};
  return screenBox(entity, modelFrame(entity), geometry);
}

bool castEntity(const EntityInstance& entity, const glm::dvec3& origin, const glm::dvec3& ray, double maxDepthM,
                EntityHit& hit) noexcept {
  if (!entity.model || entity.model->rgba.empty() || !(entity.scale > 0.0)) return false;
  return castModel(*entity.model, modelFrame(entity), origin, ray, maxDepthM, hit);
}

EntityRayHit castEntities(std::span<const EntityInstance> entities, const glm::dvec3& originM,
                          const glm::dvec3& direction, double minRangeM, double maxRangeM,
                          std::optional<std::uint32_t> excludeId, std::optional<std::uint32_t> alsoExcludeId) noexcept {
  EntityRayHit nearest;
  double limit = maxRangeM;
  for (const EntityInstance& e : entities) {
    if ((excludeId && e.id == *excludeId) || (alsoExcludeId && e.id == *alsoExcludeId)) continue;
    EntityHit hit;
    if (!castEntity(e, originM, direction, limit, hit) || hit.depthM < minRangeM) continue;
    limit = hit.depthM;  // a unit direction: the ray's parameter is the range
    nearest = {true, e.id, hit.depthM, originM + hit.depthM * direction, hit.normal, hit.rgba};
  }
  return nearest;
}

std::size_t drawEntities(std::span<const EntityInstance> entities, const ViewGeometry& geometry, const Shading& shading,
                         Frame& frame) noexcept {
  const PixelShader shader = shading.pixelShader();
  const int w = frame.intrinsics.widthPx;
  const glm::dvec3 eye = geometry.pose().positionM;
  std::size_t drawn = 0;
  for (const EntityInstance& e : entities) {
    if (!e.model || e.model->rgba.empty() || !(e.scale > 0.0)) continue;
    const ModelFrame mf = modelFrame(e);
    const PixelBox box = screenBox(e, mf, geometry);
    for (int u = box.u0; u < box.u1; ++u) {
      // The column's rows in the footprint; beyond them it repeats its end pixels, below
      const RowRun run = frame.footprint.whole ? RowRun{box.v0, box.v1} : frame.footprint.rows(u);
      for (int v = std::max(box.v0, run.first); v < std::min(box.v1, run.end); ++v) {
        std::uint8_t* row = frame.image.row(v);
        const glm::dvec3 ray = geometry.ray(u + 0.5, v + 0.5);
        const double length = glm::length(ray);
        float& rangeM =
            frame.rangeM[static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u)];
        EntityHit hit;
        if (!castModel(*e.model, mf, eye, ray, static_cast<double>(rangeM) / length, hit)) continue;
        // Lit by the frame's sun and sky (TerrainLight::model), then hazed by range as the terrain is
        const double light = shading.light().model(hit.normal);
        rangeM = static_cast<float>(hit.depthM * length);
        const Rgb lit(unpackRgb(hit.rgba).v * static_cast<float>(light));
        shader.storePixel(row + (shading.grey() ? u : 3 * u), shader.terrain(lit, rangeM), 1.0f);
        ++drawn;
      }
    }
    if (!frame.footprint.whole) {
      for (int u = box.u0; u < box.u1; ++u) repeatColumnEnds(frame, u, frame.footprint.rows(u));
    }
    // A control ray that meets the entity nearer than its terrain point records the entity's point
    for (ControlPoint& cp : frame.controlPoints) {
      const glm::dvec3 ray = geometry.ray(cp.framePx.x, cp.framePx.y);
      const double nearest =
          cp.kind == ControlPointKind::Surface ? glm::length(cp.world - eye) / glm::length(ray) : kInf;
      EntityHit hit;
      if (castModel(*e.model, mf, eye, ray, nearest, hit)) setControlPoint(cp, frame, true, eye + hit.depthM * ray);
    }
  }
  return drawn;
}

}  // namespace fieldcast::core
