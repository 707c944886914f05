#include "EmbreeHeightField.h"

#include "ShareRows.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace fieldcast::core {
namespace {

constexpr int kGridVoxels = 256;  // voxels a side of one grid primitive (257 vertices)

void check(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree: ") + what + " failed (error " +
                             std::to_string(static_cast<int>(error)) + ")");
}

}  // namespace

EmbreeHeightField::EmbreeHeightField(const LevelZeroGrid& grid) : mGrid(grid) {
  const TerrainGeometry& g = grid.geometry;
  const int w = g.widthVox, h = g.heightVox;
  const std::size_t vertices = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (vertices > std::numeric_limits<unsigned>::max()) {
    throw std::runtime_error("Embree: " + std::to_string(w) + " × " + std::to_string(h) +
                             " voxels is more vertices than its 32-bit ids number");
  }
  // One vertex more than needed: Embree reads vertices with 16-byte loads
  mVertices.resize(3 * (vertices + 1));
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      float* v = &mVertices[3 * (static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + i)];
      v[0] = static_cast<float>(i * g.spacingM);
      v[1] = static_cast<float>(j * g.spacingM);
      v[2] = grid.height(i, j);
    }
  }
  // Released by the destructor, or here when building fails
  struct Release {
    EmbreeHeightField& self;
    RTCGeometry geometry = nullptr;
    bool done = false;
    ~Release() {
      if (geometry != nullptr) rtcReleaseGeometry(geometry);
      if (done) return;
      if (self.mScene != nullptr) rtcReleaseScene(self.mScene);
      if (self.mDevice != nullptr) rtcReleaseDevice(self.mDevice);
    }
  } release{*this};
  mDevice = rtcNewDevice(nullptr);
  if (mDevice == nullptr) throw std::runtime_error("Embree: rtcNewDevice failed");
  release.geometry = rtcNewGeometry(mDevice, RTC_GEOMETRY_TYPE_GRID);
  check(mDevice, "rtcNewGeometry(GRID)");
  rtcSetSharedGeometryBuffer(release.geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, mVertices.data(), 0,
                             3 * sizeof(float), vertices);
  const int gx = (w - 1 + kGridVoxels - 1) / kGridVoxels, gy = (h - 1 + kGridVoxels - 1) / kGridVoxels;
  auto* grids = static_cast<RTCGrid*>(
      rtcSetNewGeometryBuffer(release.geometry, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, sizeof(RTCGrid),
                              static_cast<std::size_t>(gx) * static_cast<std::size_t>(gy)));
  check(mDevice, "the grid buffer");
  for (int by = 0; by < gy; ++by) {
    for (int bx = 0; bx < gx; ++bx) {
      RTCGrid& cell = grids[static_cast<std::size_t>(by) * static_cast<std::size_t>(gx) + bx];
      const int i0 = bx * kGridVoxels, j0 = by * kGridVoxels;
      cell.startVertexID = static_cast<unsigned>(static_cast<std::size_t>(j0) * static_cast<std::size_t>(w) + i0);
      cell.stride = static_cast<unsigned>(w);
      cell.width = static_cast<unsigned short>(std::min(kGridVoxels, w - 1 - i0) + 1);
      cell.height = static_cast<unsigned short>(std::min(kGridVoxels, h - 1 - j0) + 1);
    }
  }
  rtcCommitGeometry(release.geometry);
  mScene = rtcNewScene(mDevice);
  rtcAttachGeometry(mScene, release.geometry);
  rtcCommitScene(mScene);
  check(mDevice, "building the scene");
  release.done = true;
}

EmbreeHeightField::~EmbreeHeightField() {
  if (mScene != nullptr) rtcReleaseScene(mScene);
  if (mDevice != nullptr) rtcReleaseDevice(mDevice);
}

std::size_t EmbreeHeightField::render(const ViewGeometry& view, int threads, std::vector<std::uint8_t>& rgb,
                                      std::vector<float>* rangeM) const {
  const Intrinsics& k = view.intrinsics();
  const TerrainGeometry& g = mGrid.geometry;
  const std::size_t pixels = static_cast<std::size_t>(k.widthPx) * static_cast<std::size_t>(k.heightPx);
  rgb.assign(pixels * 3, 0);
  if (rangeM != nullptr) rangeM->assign(pixels, std::numeric_limits<float>::infinity());
  const glm::dvec3 eye = view.pose().positionM - glm::dvec3{g.originM.x, g.originM.y, 0.0};
  std::atomic<std::size_t> hits{0};
  shareRows(k.heightPx, 4, threads, [&](int v0, int v1) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    std::size_t found = 0;
    for (int u0 = 0; u0 < k.widthPx; u0 += 4) {
      alignas(64) RTCRayHit16 packet;
      alignas(64) int valid[16];
      for (int lane = 0; lane < 16; ++lane) {
        const int u = u0 + lane % 4, v = v0 + lane / 4;
        valid[lane] = u < k.widthPx && v < v1 ? -1 : 0;
        const glm::dvec3 dir = view.ray(u + 0.5, v + 0.5);
        packet.ray.org_x[lane] = static_cast<float>(eye.x);
        packet.ray.org_y[lane] = static_cast<float>(eye.y);
        packet.ray.org_z[lane] = static_cast<float>(eye.z);
        packet.ray.dir_x[lane] = static_cast<float>(dir.x);
        packet.ray.dir_y[lane] = static_cast<float>(dir.y);
        packet.ray.dir_z[lane] = static_cast<float>(dir.z);
        packet.ray.tnear[lane] = 0.0f;
        packet.ray.tfar[lane] = std::numeric_limits<float>::infinity();
        packet.ray.time[lane] = 0.0f;
        packet.ray.mask[lane] = ~0u;
        packet.ray.id[lane] = static_cast<unsigned>(lane);
        packet.ray.flags[lane] = 0;
        packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, mScene, &context, &packet);
      for (int lane = 0; lane < 16; ++lane) {
        if (valid[lane] == 0 || packet.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID) continue;
        const float t = packet.ray.tfar[lane];
        const double x = eye.x + t * packet.ray.dir_x[lane], y = eye.y + t * packet.ray.dir_y[lane];
        const int i = std::clamp(static_cast<int>(std::lround(x / g.spacingM)), 0, g.widthVox - 1);
        const int j = std::clamp(static_cast<int>(std::lround(y / g.spacingM)), 0, g.heightVox - 1);
        const std::uint32_t c = mGrid.colour(i, j);
        const int u = u0 + lane % 4, v = v0 + lane / 4;
        const std::size_t at = static_cast<std::size_t>(v) * static_cast<std::size_t>(k.widthPx) + u;
        if (rangeM != nullptr) {
          const float dx = packet.ray.dir_x[lane], dy = packet.ray.dir_y[lane], dz = packet.ray.dir_z[lane];
          (*rangeM)[at] = t * std::sqrt(dx * dx + dy * dy + dz * dz);
        }
        std::uint8_t* px = &rgb[3 * at];
        px[0] = static_cast<std::uint8_t>(c);
        px[1] = static_cast<std::uint8_t>(c >> 8);
        px[2] = static_cast<std::uint8_t>(c >> 16);
        ++found;
      }
    }
    hits += found;
  });
  return hits;
}

}  // namespace fieldcast::core
