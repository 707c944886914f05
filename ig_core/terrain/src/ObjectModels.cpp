// The built-in voxel models. Colours are listed from the top of each stick down; a building's wall
// texture is made from heights above the ground (window rows at the same height on every column),
// so columns of different heights line up.
#include <ig_core/ObjectModels.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace fieldcast::core {
namespace {

constexpr std::uint32_t rgb(std::uint32_t r, std::uint32_t g, std::uint32_t b) {
  return r | (g << 8) | (b << 16) | 0xFF000000u;
}

constexpr std::uint32_t kCrownDark = rgb(34, 62, 30);
constexpr std::uint32_t kCrownMid = rgb(44, 78, 36);
constexpr std::uint32_t kLeafLight = rgb(70, 104, 44);
constexpr std::uint32_t kLeafMid = rgb(58, 92, 40);
constexpr std::uint32_t kTrunk = rgb(84, 62, 44);
constexpr std::uint32_t kHedge = rgb(40, 70, 34);
constexpr std::uint32_t kRoofTiles = rgb(150, 64, 46);
constexpr std::uint32_t kRoofSlate = rgb(70, 72, 80);
constexpr std::uint32_t kRender = rgb(226, 214, 188);
constexpr std::uint32_t kStone = rgb(168, 162, 150);
constexpr std::uint32_t kTimber = rgb(120, 84, 56);
constexpr std::uint32_t kWindow = rgb(44, 52, 64);
constexpr std::uint32_t kDoor = rgb(70, 46, 32);

// A textured stick of `units` stick voxels whose colour at height h (metres above its foot, at
// the voxel's middle) is colourAt(h, fromTop) — fromTop: metres below its top.
StickEntry columnOf(int units, const std::function<std::uint32_t(double, double)>& colourAt) {
  StickEntry e;
  e.kind = StickKind::Textured;
  e.lengthVox = static_cast<std::uint32_t>(units);
  for (int k = 0; k < units; ++k) {
    const double fromTop = (k + 0.5) * kModelStickUnitM;
    e.texels.push_back(colourAt(units * kModelStickUnitM - fromTop, fromTop));
  }
  return e;
}

// A building's wall at height h: window rows (from 1.0 to 2.0 m and from 3.6 to 4.6 m above the
// ground, when the wall is that tall), otherwise the wall's colour.
std::uint32_t wallAt(double h, double wallTopM, std::uint32_t wall) {
  const bool window = (h > 1.0 && h < 2.0) || (h > 3.6 && h < 4.6 && wallTopM > 5.0);
  return window ? kWindow : wall;
}

VoxelModel conifer() {
  VoxelModel m{"conifer", 2.0, 1, 1, {{1, 32}}, {}};
  m.sticks.push_back(columnOf(32, [](double h, double) {
    if (h < 3.0) return kTrunk;
    return static_cast<int>(h / 1.5) % 2 == 0 ? kCrownDark : kCrownMid;  // whorls of branches
  }));
  return m;
}

VoxelModel broadleaf() {
  // A dome three cells across over a trunk 2 m tall: under the crown around the trunk, a cavity
  VoxelModel m{"broadleaf", 2.0, 3, 3, {}, {}};
  const auto crown = [](int units, bool trunk) {
    StickEntry e = columnOf(units, [trunk](double h, double fromTop) {
      if (h < 2.0) return trunk ? kTrunk : kCavityRgba;
      return fromTop < 1.0 ? kLeafLight : kLeafMid;
    });
    if (!trunk) e.kind = StickKind::Complex;
    return e;
  };
  m.sticks = {crown(24, true), crown(20, false), crown(16, false)};
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) {
      const int ring = (x != 1) + (y != 1);  // 0 centre, 1 sides, 2 corners
      m.columns.push_back({static_cast<std::uint32_t>(ring + 1), 24 - 4 * ring});
    }
  return m;
}

VoxelModel hedge() { return VoxelModel{"hedge", 2.0, 1, 1, {{1, 3}}, {StickEntry{StickKind::Uniform, 3, {kHedge}}}}; }

// A house or barn: widthCells × depthCells, walls `wallUnits` tall under a gable roof whose ridge
// runs east-west, `roofUnits` above the eaves; windows in every other column (with `windows`), and
// with `door` a door in the middle of the south wall.
VoxelModel gabled(const char* name, int widthCells, int depthCells, int wallUnits, int roofUnits, std::uint32_t wall,
                  std::uint32_t roof, bool windows, bool door) {
  VoxelModel m{name, 2.0, widthCells, depthCells, {}, {}};
  const double wallTopM = wallUnits * kModelStickUnitM;
  const auto wallColumn = [=](int units, bool withWindows, bool withDoor) {
    return columnOf(units, [=](double h, double) {
      if (h >= wallTopM) return roof;
      if (withDoor && h < 2.2) return kDoor;
      return withWindows ? wallAt(h, wallTopM, wall) : wall;
    });
  };
  for (int y = 0; y < depthCells; ++y) {
    // The roof rises from the eaves (first and last rows) to the ridge (the middle)
    const double toRidge = 1.0 - std::abs((y + 0.5) - depthCells / 2.0) / (depthCells / 2.0);
    const int units = wallUnits + 1 + static_cast<int>(std::lround(toRidge * roofUnits));
    m.sticks.push_back(wallColumn(units, false, false));
    const auto pier = static_cast<std::uint32_t>(m.sticks.size());
    m.sticks.push_back(wallColumn(units, windows, false));
    const auto window = static_cast<std::uint32_t>(m.sticks.size());
    for (int x = 0; x < widthCells; ++x) m.columns.push_back({x % 2 == 1 ? window : pier, units});
  }
  if (door) {
    m.sticks.push_back(wallColumn(m.columns[0].heightUnits, false, true));
    m.columns[static_cast<std::size_t>(widthCells / 2)].stick = static_cast<std::uint32_t>(m.sticks.size());
  }
  return m;
}

VoxelModel church() {
  // A nave 5 × 10 cells (10 × 20 m) under a slate roof running north-south, and a stone tower of
  // 3 × 3 cells at its south end, 20 m, with a spire to 30 m
  VoxelModel m{"church", 2.0, 5, 13, {}, {}};
  const VoxelModel nave = gabled("nave", 10, 5, 18, 10, kStone, kRoofSlate, true, false);  // 5 rows, ridge east-west
  m.sticks = nave.sticks;
  const auto belfry = [](double h) { return (h > 14.0 && h < 16.0) ? kWindow : kStone; };
  m.sticks.push_back(columnOf(40, [&](double h, double) { return belfry(h); }));
  const auto towerWall = static_cast<std::uint32_t>(m.sticks.size());
  m.sticks.push_back(columnOf(60, [&](double h, double) { return h > 20.0 ? kRoofSlate : belfry(h); }));
  const auto spire = static_cast<std::uint32_t>(m.sticks.size());
  m.columns.assign(static_cast<std::size_t>(m.widthCells * m.depthCells), VoxelModel::Column{});
  for (int y = 0; y < 3; ++y)
    for (int x = 1; x <= 3; ++x) {
      const bool centre = x == 2 && y == 1;
      m.columns[static_cast<std::size_t>(y * m.widthCells + x)] = {centre ? spire : towerWall, centre ? 60 : 40};
    }
  // Rows 3–12: the nave turned north-south (its row across the nave is the column x here; along
  // it, piers and windows alternate)
  for (int y = 3; y < 13; ++y)
    for (int x = 0; x < 5; ++x)
      m.columns[static_cast<std::size_t>(y * m.widthCells + x)] =
          nave.columns[static_cast<std::size_t>(x * 10 + y % 2)];
  return m;
}

std::vector<VoxelModel> makeLibrary() {
  return {conifer(),
          broadleaf(),
          hedge(),
          gabled("house", 5, 4, 11, 6, kRender, kRoofTiles, true, true),
          gabled("barn", 8, 5, 12, 8, kTimber, kRoofSlate, false, true),
          church()};
}

}  // namespace

const std::vector<VoxelModel>& builtinModels() {
  static const std::vector<VoxelModel> library = makeLibrary();
  return library;
}

const VoxelModel* findBuiltinModel(const std::string& name) {
  const std::vector<VoxelModel>& library = builtinModels();
  const auto it = std::find_if(library.begin(), library.end(), [&](const VoxelModel& m) { return m.name == name; });
  return it == library.end() ? nullptr : &*it;
}

}  // namespace fieldcast::core
