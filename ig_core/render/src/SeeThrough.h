#pragma once
// Secondary rays through complex sticks (ig_core/README.md, "Sticks"). A primary ray that meets a
// see-through texel of a complex stick (alpha below 255: a cavity, or semi-transparent) goes on
// from its hit as a secondary ray. Near objects the height field cannot say what lies under a
// crown or a deck, so the secondary ray walks level-0 voxel columns as boxes (Amanatides & Woo):
// a column is solid below its top where its stick's texel at that depth is opaque, and below a
// complex stick's foot (the ground, in the voxel's colour); the column it starts in, unless it
// holds a complex stick (whose texels are walked from the start), only through its top from a
// start above it (the hit lies on the surface between voxel centres, which may dip under a box's
// top) — a start inside that box passes through it, but is met where it starts when it would
// leave the column under that surface or, going down, never leave it (a vertical ray);
// semi-transparent texels are blended front to back. Two stick-free columns in a row, above
// the height field's surface there, and it has left the objects: the per-ray march (RayMarch.h)
// takes it on from there over the terrain. Only level 0 sees through (coarser levels' cavities are
// filled), so far objects cost no secondary ray. Private to ig_core.

#include "ColumnCaster.h"
#include "TileWindows.h"

#include <glm/vec3.hpp>

#include <cstdint>

namespace fieldcast::core {

/// What a ray sees through a see-through texel: the colour (hazed, the layers blended) and the
/// range (m) of the first surface it met that is at least half opaque, infinite for the sky.
struct SeenThrough {
  Rgb colour;
  float rangeM = 0.0f;
};

/// The ray of direction `d` (forward component 1, as ViewGeometry::ray gives it) met a see-through
/// texel at depth `depthM`: what it sees from there, the walk blending that texel as it passes its
/// column (once, however many rows' rays met it on the surface between voxel centres). Counts a
/// secondary ray in t.secondaryRays. Reads level 0 through `window` (TileWindows.h: a secondary
/// ray walks two or three columns, and a fresh window would first look up their tile). RT-safe.
SeenThrough seeThrough(const CasterFrame& f, CasterThread& t, const glm::dvec3& d, double depthM,
                       TileWindows& window) noexcept;

}  // namespace fieldcast::core
