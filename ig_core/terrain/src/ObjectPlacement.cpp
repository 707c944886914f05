#include <ig_core/ObjectPlacement.h>

#include "Parallel.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace fieldcast::core {
namespace {

std::string trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return {};
  return s.substr(begin, s.find_last_not_of(" \t\r") - begin + 1);
}

std::vector<std::string> splitCells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

std::string knownModels() {
  std::string names;
  for (const VoxelModel& m : builtinModels()) names += (names.empty() ? "" : ", ") + m.name;
  return names;
}

}  // namespace

std::vector<ObjectPlacement> readPlacementList(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open the placement list");
  std::vector<ObjectPlacement> objects;
  std::vector<std::string> header;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string where = path.string() + ":" + std::to_string(number) + ": ";
    const std::string content = trim(line);
    if (content.empty() || content[0] == '#') continue;
    const std::vector<std::string> cells = splitCells(content);
    if (header.empty()) {
      header = cells;
      const bool known = header.size() >= 3 && header.size() <= 5 && header[0] == "model" && header[1] == "x" &&
                         header[2] == "y" && (header.size() < 4 || header[3] == "heading") &&
                         (header.size() < 5 || header[4] == "scale");
      if (!known) throw std::runtime_error(where + "the header must be model,x,y[,heading[,scale]], not " + content);
      continue;
    }
    if (cells.size() != header.size()) {
      throw std::runtime_error(where + std::to_string(cells.size()) + " values, the header has " +
                               std::to_string(header.size()));
    }
    ObjectPlacement p;
    p.model = cells[0];
    const auto number_ = [&](std::size_t k) {
      std::size_t used = 0;
      double value = 0.0;
      try {
        value = std::stod(cells[k], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != cells[k].size() || cells[k].empty() || !std::isfinite(value)) {
        throw std::runtime_error(where + header[k] + " '" + cells[k] + "' is not a number");
      }
      return value;
    };
    p.xM = number_(1);
    p.yM = number_(2);
    if (cells.size() > 3) p.headingDeg = number_(3);
    if (cells.size() > 4) p.scale = number_(4);
    if (p.scale < kMinObjectScale || p.scale > kMaxObjectScale) {
      throw std::runtime_error(where + "scale " + cells[4] + " out of range " + std::to_string(kMinObjectScale) +
                               " .. " + std::to_string(kMaxObjectScale));
    }
    objects.push_back(std::move(p));
  }
  if (header.empty()) throw std::runtime_error(path.string() + ": empty placement list (no header)");
  return objects;
}

ObjectPlacer::ObjectPlacer(TerrainGrid& grid) : mGrid(grid) {
  const TerrainGeometry& g = grid.geometry;
  const std::size_t count = static_cast<std::size_t>(g.widthVox) * static_cast<std::size_t>(g.heightVox);
  if (grid.heightQ.size() != count || grid.colourRgba.size() != count ||
      (!grid.stickId.empty() && grid.stickId.size() != count)) {
    throw std::invalid_argument("placing objects: the grid's arrays do not match its size");
  }
  if (grid.stickId.empty()) grid.stickId.assign(count, 0u);
  if (grid.sticks) {
    if (std::abs(grid.sticks->unitM() - kModelStickUnitM) > 1e-12) {
      throw std::invalid_argument("placing objects: the grid's stick table has another unit than the models'");
    }
    for (std::uint32_t id = 1; id <= grid.sticks->size(); ++id) mEntries.push_back(grid.sticks->entry(id));
  }
  mGround = grid.groundQ.size() == count ? std::move(grid.groundQ) : grid.heightQ;
}

bool ObjectPlacer::place(const VoxelModel& model, double xM, double yM, double headingDeg, double scale) {
  findFootprint(PlacementRequest{&model, xM, yM, headingDeg, scale}, mFootprint);
  return apply(mFootprint);
}

void ObjectPlacer::place(std::span<const PlacementRequest> requests, int threads) {
  std::vector<Footprint> footprints(std::min(kBatchRequests, requests.size()));
  std::vector<std::exception_ptr> errors(footprints.size());
  for (std::size_t first = 0; first < requests.size(); first += kBatchRequests) {
    const std::size_t count = std::min(kBatchRequests, requests.size() - first);
    detail::parallelFor(count, threads, 64, [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) {
        errors[k] = nullptr;
        try {
          findFootprint(requests[first + k], footprints[k]);
        } catch (...) {
          errors[k] = std::current_exception();
        }
      }
    });
    for (std::size_t k = 0; k < count; ++k) {  // in order: where objects overlap, order decides ties
      if (errors[k]) std::rethrow_exception(errors[k]);
      apply(footprints[k]);
    }
  }
}

void ObjectPlacer::findFootprint(const PlacementRequest& request, Footprint& out) const {
  if (request.model == nullptr) throw std::invalid_argument("placement without a model");
  const VoxelModel& model = *request.model;
  const double xM = request.xM, yM = request.yM, headingDeg = request.headingDeg, scale = request.scale;
  const TerrainGeometry& g = mGrid.geometry;
  // Positions within a million grid widths of the grid: far enough for anything meant, near enough
  // that the voxel ranges below stay in int
  const double reachM = 1e6 * g.spacingM * std::max(g.widthVox, g.heightVox);
  if (!(scale >= kMinObjectScale && scale <= kMaxObjectScale) || !(std::abs(xM - g.originM.x) < reachM) ||
      !(std::abs(yM - g.originM.y) < reachM) || !std::isfinite(headingDeg)) {
    throw std::invalid_argument("placement of '" + model.name + "': a position, heading or scale out of range");
  }
  if (model.widthCells < 1 || model.depthCells < 1 || !(model.cellM > 0.0) ||
      model.columns.size() != static_cast<std::size_t>(model.widthCells) * static_cast<std::size_t>(model.depthCells)) {
    throw std::invalid_argument("model '" + model.name + "': its columns do not match its size");
  }
  // The voxels whose centres fall in the model's rotated footprint, with their cells
  const double cell = model.cellM * scale;
  const double heading = headingDeg * std::numbers::pi / 180.0;
  const double rightX = std::cos(heading), rightY = -std::sin(heading);     // the model's x axis in the world
  const double forwardX = std::sin(heading), forwardY = std::cos(heading);  // its y axis
  const double radius = 0.5 * cell * std::hypot(model.widthCells, model.depthCells);
  const auto voxel = [](double v, int last) { return static_cast<int>(std::clamp(v, -1.0, last + 1.0)); };
  const int i0 = std::max(0, voxel(std::floor((xM - radius - g.originM.x) / g.spacingM), g.widthVox));
  const int i1 = std::min(g.widthVox - 1, voxel(std::ceil((xM + radius - g.originM.x) / g.spacingM), g.widthVox));
  const int j0 = std::max(0, voxel(std::floor((yM - radius - g.originM.y) / g.spacingM), g.heightVox));
  const int j1 = std::min(g.heightVox - 1, voxel(std::ceil((yM + radius - g.originM.y) / g.spacingM), g.heightVox));
  out.model = &model;
  out.voxels.clear();
  std::uint16_t baseQ = 65535;
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      const double dx = g.originM.x + i * g.spacingM - xM;
      const double dy = g.originM.y + j * g.spacingM - yM;
      const double mx = (dx * rightX + dy * rightY) / cell + 0.5 * model.widthCells;
      const double my = (dx * forwardX + dy * forwardY) / cell + 0.5 * model.depthCells;
      if (mx < 0.0 || my < 0.0 || mx >= model.widthCells || my >= model.depthCells) continue;
      const VoxelModel::Column& column =
          model.columns[static_cast<std::size_t>(static_cast<int>(my) * model.widthCells + static_cast<int>(mx))];
      if (column.stick == 0) continue;
      if (column.stick > model.sticks.size()) {
        throw std::invalid_argument("model '" + model.name + "': a column names stick " + std::to_string(column.stick) +
                                    " of " + std::to_string(model.sticks.size()));
      }
      const std::size_t k = static_cast<std::size_t>(j) * static_cast<std::size_t>(g.widthVox) + i;
      out.voxels.push_back({k, column.stick, 0, column.heightUnits});
      baseQ = std::min(baseQ, mGround[k]);
    }
  }
  // Each voxel's top over the lowest ground; voxels buried by the slope dropped
  std::size_t kept = 0;
  for (FootprintVoxel v : out.voxels) {
    const double topM = g.heightM(baseQ) + v.heightUnits * kModelStickUnitM * scale;
    v.topQ = static_cast<std::uint16_t>(std::clamp(std::lround((topM - g.heightBaseM) / g.heightStepM), 0L, 65535L));
    if (v.topQ <= mGround[v.k]) continue;
    // A complex stick reaches down to this voxel's ground, its texels stretched or squeezed to the
    // length (a tree's gap under its crown stays open to the ground however it is scaled, and on a
    // slope ends on the ground here, not under the lowest ground of the footprint): an entry per
    // model stick and length placed. Others keep the model's entry, its last colour filling a
    // longer stick, a shorter one losing its foot.
    v.placedLength = 0;
    if (model.sticks[v.stick - 1].kind == StickKind::Complex) {
      v.placedLength =
          static_cast<std::uint32_t>(std::clamp(std::lround((v.topQ - mGround[v.k]) * g.heightStepM / kModelStickUnitM),
                                                1L, static_cast<long>(kMaxStickLength)));
    }
    out.voxels[kept++] = v;
  }
  out.voxels.resize(kept);
}

std::uint32_t ObjectPlacer::tableId(const VoxelModel& model, std::uint32_t stick, std::uint32_t placedLength) {
  const auto key = std::make_tuple(&model, stick, placedLength);
  if (const auto it = mIdOf.find(key); it != mIdOf.end()) return it->second;
  const StickEntry& modelEntry = model.sticks[stick - 1];
  StickEntry entry = modelEntry;
  if (placedLength != 0) {
    entry.lengthVox = placedLength;
    entry.texels.resize(placedLength);
    for (std::uint32_t u = 0; u < placedLength; ++u) {  // the model's texel under each one's middle
      const std::size_t from = (2 * u + 1) * modelEntry.texels.size() / (2 * placedLength);
      entry.texels[u] = modelEntry.texels[from];
    }
  }
  mEntries.push_back(std::move(entry));
  const auto id = static_cast<std::uint32_t>(mEntries.size());
  mIdOf.emplace(key, id);
  return id;
}

bool ObjectPlacer::apply(const Footprint& footprint) {
  const VoxelModel& model = *footprint.model;
  bool any = false;
  // Neighbouring voxels mostly carry the same stick: its id is looked up once for a run of them
  std::uint32_t lastStick = 0, lastLength = 0, lastId = 0;
  for (const FootprintVoxel& v : footprint.voxels) {
    if (mGrid.stickId[v.k] != 0 && mGrid.heightQ[v.k] >= v.topQ) continue;  // a taller stick is there
    if (v.stick != lastStick || v.placedLength != lastLength || lastId == 0) {
      lastStick = v.stick;
      lastLength = v.placedLength;
      lastId = tableId(model, v.stick, v.placedLength);
    }
    mGrid.heightQ[v.k] = v.topQ;
    mGrid.stickId[v.k] = lastId;
    // The voxel's colour: the top's, for coarse levels; a complex stick keeps the ground's, which
    // its cavities show below it (unless another stick stood there before)
    const StickEntry& modelEntry = model.sticks[v.stick - 1];
    if (modelEntry.kind != StickKind::Complex) mGrid.colourRgba[v.k] = modelEntry.texels.front();
    any = true;
  }
  ++(any ? mReport.placed : mReport.offGrid);
  return any;
}

PlacementReport ObjectPlacer::finish() {
  mGrid.sticks = std::make_shared<const StickTable>(kModelStickUnitM, std::move(mEntries));
  mGrid.groundQ = std::move(mGround);  // for a later placer: the ground, not these objects' tops
  mReport.tableEntries = mGrid.sticks->size();
  mReport.stickVoxels = static_cast<std::size_t>(
      std::count_if(mGrid.stickId.begin(), mGrid.stickId.end(), [](std::uint32_t id) { return id != 0; }));
  return mReport;
}

PlacementReport placeObjects(TerrainGrid& grid, std::span<const ObjectPlacement> objects, const ModelLookup& lookup,
                             int threads) {
  std::vector<PlacementRequest> requests;
  requests.reserve(objects.size());
  for (const ObjectPlacement& p : objects) {
    const VoxelModel* model = lookup(p.model);
    if (model == nullptr) {
      throw std::invalid_argument("unknown model '" + p.model + "' (built in: " + knownModels() +
                                  "; or a .vox file named by its path)");
    }
    requests.push_back({model, p.xM, p.yM, p.headingDeg, p.scale});
  }
  ObjectPlacer placer(grid);
  placer.place(requests, threads);
  return placer.finish();
}

}  // namespace fieldcast::core
