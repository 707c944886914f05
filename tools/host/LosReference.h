#pragma once
// The scripted host's own answer to a Line of Sight Segment request, to judge the IG's: a plain
// march along the segment in fine steps over the bilinear level-0 surface (TerrainView::heightAtM),
// independent of the IG's march (core::lineOfSight, 1/8-voxel steps refined by bisection).

#include <ig_core/TerrainView.h>

#include <glm/vec3.hpp>

#include <optional>

namespace fieldcast::tools {

/// Distance in metres from `fromM` to the first point of the segment `fromM`→`toM` (world metres)
/// that lies on or below the level-0 surface, sampled every `stepVoxels` voxel along the segment
/// and only over the hull of the level-0 voxel centres (where the IG searches: outside it there is
/// no terrain). nullopt when the segment stays above. Reads whatever tiles are resident: make the
/// level-0 tiles along the segment resident first for the full-resolution answer.
std::optional<double> referenceSegmentRangeM(const core::TerrainView& view, const glm::dvec3& fromM,
                                             const glm::dvec3& toM, double stepVoxels = 1.0 / 32.0);

}  // namespace fieldcast::tools
