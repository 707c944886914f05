#pragma once
// The column-plane march (PlaneMarch.h) for neighbouring columns in step: the lanes of a block of
// up to kLaneColumns columns whose planes share their major axis and direction cross the same grid
// lines at the same level, one line after another, so the work of a line (its solve for each
// column, the height reads, the bookkeeping) is the same instructions for every column — the form
// SIMD lanes take (issue 24). Each lane solves its column's crossing on every line (the one-column
// march skips the lines whose crossing cannot fill a row by marching the next row's ray instead);
// the fills between crossings stay the column's own (CrossingFill.h).
//
// The block shares its level: it switches to the coarser one only where every column's march
// would (each column's last crossing lies past its switch depth), and not while a column still to
// join would start its own march at that level or a finer one, so no column is drawn coarser than
// its own march draws it; the nearer columns of a block are drawn finer than that. A column joins
// the block at the block's level, on the grid line at or before where its bottom rays left it.
// Private to ig_core.

#include "PlaneMarch.h"

#include <glm/vec2.hpp>

#include <span>

namespace fieldcast::core::plane_march {

/// The columns a block marches in step, at most.
constexpr int kLaneColumns = 8;

/// One column of a lane block: where its plane march starts, and where it stopped.
struct LaneColumn {
  ColumnSink* sink = nullptr;
  const ColumnPlane* plane = nullptr;
  int q = -1;  ///< in: the first sub-row to fill; out: the first it could not fill (above the sink's qTop: full)
  glm::dvec2 start{0.0};      ///< level-0 x, y of the hit of the ray of sub-row q + 1
  int level = 0;              ///< the level that hit was found at
  PlaneStop stopped;          ///< out: the march's last crossing, as marchPlane records it
  RowsPassedOver passedOver;  ///< out: rows that see terrain the march passed over
};

/// marchPlane for up to kLaneColumns columns whose planes share their major axis and direction
/// (ColumnPlane::xMajor, sx), marched in step: fills each column's sub-rows from its q down, and
/// leaves in q and stopped what marchPlane returns and records (the rows left, where its march
/// ended, whether those rows look over the terrain). RT-safe, allocation-free.
void marchLanes(const CasterFrame& f, CasterThread& t, std::span<LaneColumn> columns, TileWindows& window) noexcept;

}  // namespace fieldcast::core::plane_march
