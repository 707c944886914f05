// MagicaVoxel .vox, version 150 (github.com/ephtracy/voxel-model, MagicaVoxel-file-format-vox.txt):
// "VOX " and the version; a MAIN chunk whose children are SIZE (x, y, z), XYZI (a count, then
// x, y, z, colour index bytes) and RGBA (256 colours; index i is entry i - 1). Every chunk is its
// id, its content's size, its children's size, both little-endian. Palette reduction by median cut
// (Heckbert, "Color image quantization for frame buffer display", 1982).
#include <ig_core/VoxFile.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

namespace fieldcast::core {
namespace {

constexpr int kMaxVoxSide = 256;
constexpr std::size_t kMaxPalette = 255;  // index 0 is empty

std::uint32_t readU32(const std::vector<unsigned char>& bytes, std::size_t at) {
  return static_cast<std::uint32_t>(bytes[at]) | (static_cast<std::uint32_t>(bytes[at + 1]) << 8) |
         (static_cast<std::uint32_t>(bytes[at + 2]) << 16) | (static_cast<std::uint32_t>(bytes[at + 3]) << 24);
}

void appendU32(std::vector<unsigned char>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
}

void appendChunk(std::vector<unsigned char>& out, const char* id, const std::vector<unsigned char>& content) {
  out.insert(out.end(), id, id + 4);
  appendU32(out, static_cast<std::uint32_t>(content.size()));
  appendU32(out, 0);
  out.insert(out.end(), content.begin(), content.end());
}

int channel(std::uint32_t rgba, int c) { return static_cast<int>((rgba >> (8 * c)) & 0xFFu); }

// Median cut: split the box of colours with the widest channel at its median until there are
// `count` boxes; each box's palette entry is its colours' mean, weighted by use.
std::vector<std::uint32_t> medianCut(const std::map<std::uint32_t, std::size_t>& uses, std::size_t count) {
  using Box = std::vector<std::pair<std::uint32_t, std::size_t>>;
  std::vector<Box> boxes{Box(uses.begin(), uses.end())};
  const auto widest = [](const Box& box, int& which) {
    int best = -1;
    for (int c = 0; c < 3; ++c) {
      const auto [lo, hi] = std::minmax_element(box.begin(), box.end(), [c](const auto& a, const auto& b) {
        return channel(a.first, c) < channel(b.first, c);
      });
      const int range = channel(hi->first, c) - channel(lo->first, c);
      if (range > best) best = range, which = c;
    }
    return best;
  };
  while (boxes.size() < count) {
    int channelOfSplit = 0, widestRange = 0;
    std::size_t split = boxes.size();
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      int c = 0;
      const int range = boxes[b].size() > 1 ? widest(boxes[b], c) : 0;
      if (range > widestRange) widestRange = range, split = b, channelOfSplit = c;
    }
    if (split == boxes.size()) break;
    Box& box = boxes[split];
    std::sort(box.begin(), box.end(), [&](const auto& a, const auto& b) {
      return channel(a.first, channelOfSplit) < channel(b.first, channelOfSplit);
    });
    Box upper(box.begin() + static_cast<std::ptrdiff_t>(box.size() / 2), box.end());
    box.resize(box.size() / 2);
    boxes.push_back(std::move(upper));
  }
  std::vector<std::uint32_t> palette;
  for (const Box& box : boxes) {
    std::array<double, 3> sum{};
    double weight = 0.0;
    for (const auto& [colour, n] : box) {
      for (int c = 0; c < 3; ++c)
        sum[static_cast<std::size_t>(c)] += static_cast<double>(channel(colour, c)) * static_cast<double>(n);
      weight += static_cast<double>(n);
    }
    std::uint32_t entry = 0xFF000000u;
    for (int c = 0; c < 3; ++c)
      entry |= static_cast<std::uint32_t>(sum[static_cast<std::size_t>(c)] / weight + 0.5) << (8 * c);
    palette.push_back(entry);
  }
  return palette;
}

}  // namespace

VoxelSolid readVoxFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw VoxFileError(path.string() + ": cannot open the .vox file");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto fail = [&](const std::string& what) { return VoxFileError(path.string() + ": " + what); };
  if (bytes.size() < 20 || std::memcmp(bytes.data(), "VOX ", 4) != 0) throw fail("not a MagicaVoxel .vox file");
  if (std::memcmp(bytes.data() + 8, "MAIN", 4) != 0) throw fail("no MAIN chunk after the header");

  int sizes = 0;
  std::array<int, 3> size{};
  std::vector<unsigned char> voxels;  // x, y, z, colour index
  bool haveVoxels = false;
  std::array<std::uint32_t, 256> palette{};
  bool havePalette = false;
  // The MAIN chunk's content (normally empty), then its children in sequence
  std::size_t at = 20 + static_cast<std::size_t>(readU32(bytes, 12));
  while (at < bytes.size()) {
    if (bytes.size() - at < 12) throw fail("a chunk header cut off at byte " + std::to_string(at));
    const std::string id(reinterpret_cast<const char*>(bytes.data() + at), 4);
    const std::uint64_t content = readU32(bytes, at + 4), children = readU32(bytes, at + 8);
    const std::size_t body = at + 12;
    if (content + children > bytes.size() - body) throw fail("chunk " + id + " runs past the end of the file");
    if (id == "SIZE") {
      if (++sizes > 1) throw fail("several models (SIZE chunks); fieldcast reads a file of one");
      if (content < 12) throw fail("a SIZE chunk of " + std::to_string(content) + " bytes");
      const std::array<std::uint32_t, 3> given{readU32(bytes, body), readU32(bytes, body + 4),
                                               readU32(bytes, body + 8)};
      if (std::any_of(given.begin(), given.end(), [](std::uint32_t n) { return n < 1 || n > kMaxVoxSide; })) {
        throw fail("a model of " + std::to_string(given[0]) + " × " + std::to_string(given[1]) + " × " +
                   std::to_string(given[2]) + " voxels (each side 1 … 256)");
      }
      for (std::size_t c = 0; c < 3; ++c) size[c] = static_cast<int>(given[c]);
    } else if (id == "XYZI") {
      if (content < 4) throw fail("an XYZI chunk of " + std::to_string(content) + " bytes");
      const std::uint64_t count = readU32(bytes, body);
      if (4 + 4 * count > content) throw fail("an XYZI chunk says " + std::to_string(count) + " voxels, holds fewer");
      voxels.assign(bytes.begin() + static_cast<std::ptrdiff_t>(body + 4),
                    bytes.begin() + static_cast<std::ptrdiff_t>(body + 4 + 4 * count));
      haveVoxels = true;
    } else if (id == "RGBA") {
      if (content < 1024) throw fail("an RGBA chunk of " + std::to_string(content) + " bytes, not 1024");
      for (std::size_t i = 0; i < 256; ++i) palette[i] = readU32(bytes, body + 4 * i);
      havePalette = true;
    }
    at = body + content + children;  // children of other chunks (scene graph) are skipped whole
  }
  if (sizes == 0 || !haveVoxels) throw fail("no model (SIZE and XYZI chunks)");
  if (!havePalette) throw fail("no RGBA palette chunk (files on MagicaVoxel's default palette: save with the palette)");

  VoxelSolid solid = emptySolid(size[0], size[1], size[2]);
  for (std::size_t v = 0; v < voxels.size(); v += 4) {
    const int x = voxels[v], y = voxels[v + 1], z = voxels[v + 2], colour = voxels[v + 3];
    if (x >= size[0] || y >= size[1] || z >= size[2]) {
      throw fail("voxel " + std::to_string(v / 4) + " at (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
                 std::to_string(z) + ") lies outside the model's size");
    }
    if (colour == 0) continue;  // index 0 is no voxel
    solid.rgba[solid.index(x, y, z)] = palette[static_cast<std::size_t>(colour - 1)] | 0xFF000000u;
  }
  return solid;
}

VoxWriteReport writeVoxFile(const std::filesystem::path& path, const VoxelSolid& solid) {
  if (solid.sizeX > kMaxVoxSide || solid.sizeY > kMaxVoxSide || solid.sizeZ > kMaxVoxSide) {
    throw VoxFileError(path.string() + ": a .vox model is at most 256 voxels a side, this one " +
                       std::to_string(solid.sizeX) + " × " + std::to_string(solid.sizeY) + " × " +
                       std::to_string(solid.sizeZ));
  }
  std::map<std::uint32_t, std::size_t> uses;  // opaque colour → voxels
  for (std::uint32_t c : solid.rgba)
    if ((c >> 24) != 0) ++uses[c | 0xFF000000u];
  std::vector<std::uint32_t> palette;
  if (uses.size() <= kMaxPalette) {
    for (const auto& [colour, n] : uses) palette.push_back(colour);
  } else {
    palette = medianCut(uses, kMaxPalette);
  }
  // Each colour's nearest palette entry (1-based index)
  VoxWriteReport report{static_cast<int>(palette.size()), 0};
  std::map<std::uint32_t, unsigned char> indexOf;
  for (const auto& [colour, n] : uses) {
    int best = 0, bestDistance = 1 << 30;
    for (std::size_t i = 0; i < palette.size(); ++i) {
      int distance = 0;
      for (int c = 0; c < 3; ++c) {
        const int d = channel(colour, c) - channel(palette[i], c);
        distance += d * d;
      }
      if (distance < bestDistance) bestDistance = distance, best = static_cast<int>(i);
    }
    for (int c = 0; c < 3; ++c) {
      report.maxColourError = std::max(
          report.maxColourError, std::abs(channel(colour, c) - channel(palette[static_cast<std::size_t>(best)], c)));
    }
    indexOf[colour] = static_cast<unsigned char>(best + 1);
  }

  std::vector<unsigned char> sizeChunk, voxelChunk, paletteChunk;
  for (int n : {solid.sizeX, solid.sizeY, solid.sizeZ}) appendU32(sizeChunk, static_cast<std::uint32_t>(n));
  appendU32(voxelChunk, static_cast<std::uint32_t>(solid.filledCount()));
  for (int z = 0; z < solid.sizeZ; ++z)
    for (int y = 0; y < solid.sizeY; ++y)
      for (int x = 0; x < solid.sizeX; ++x) {
        if (!solid.filled(x, y, z)) continue;
        for (int v : {x, y, z}) voxelChunk.push_back(static_cast<unsigned char>(v));
        voxelChunk.push_back(indexOf.at(solid.rgba[solid.index(x, y, z)] | 0xFF000000u));
      }
  for (std::size_t i = 0; i < 256; ++i) appendU32(paletteChunk, i < palette.size() ? palette[i] : 0xFF000000u);
  std::vector<unsigned char> children;
  appendChunk(children, "SIZE", sizeChunk);
  appendChunk(children, "XYZI", voxelChunk);
  appendChunk(children, "RGBA", paletteChunk);

  std::vector<unsigned char> file{'V', 'O', 'X', ' '};
  appendU32(file, 150);
  file.insert(file.end(), {'M', 'A', 'I', 'N'});
  appendU32(file, 0);
  appendU32(file, static_cast<std::uint32_t>(children.size()));
  file.insert(file.end(), children.begin(), children.end());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size()));
  if (!out.flush()) throw VoxFileError(path.string() + ": cannot write the .vox file");
  return report;
}

}  // namespace fieldcast::core
