#pragma once
// MagicaVoxel .vox files (format version 150: MAIN with SIZE, XYZI and RGBA chunks; the format of
// MagicaVoxel, Goxel, Blender's importers), the file fieldcast-sculpt writes and a placement list
// names. A .vox voxel is kSolidVoxelM (0.5 m) at scale 1; .vox x, y, z are the model's right, front
// and up (VoxelSolid.h).

#include <ig_core/VoxelSolid.h>

#include <filesystem>
#include <stdexcept>

namespace fieldcast::core {

/// What is wrong with a .vox file, naming the file and the chunk.
class VoxFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads the one model of a .vox file. Chunks other than SIZE, XYZI and RGBA are skipped by their
/// sizes; a file of several models, without a palette chunk, with a voxel outside its size, or
/// with a chunk past the file's end throws VoxFileError.
VoxelSolid readVoxFile(const std::filesystem::path& path);

/// How writing went: the palette's entries and how far a colour moved into it.
struct VoxWriteReport {
  int paletteEntries = 0;
  int maxColourError = 0;  ///< the largest channel difference a voxel's colour took (0: exact)
};

/// Writes `solid` (each side ≤ 256, the format's limit; VoxFileError otherwise). Up to 255
/// distinct colours are kept exactly; more are reduced to 255 by median cut.
VoxWriteReport writeVoxFile(const std::filesystem::path& path, const VoxelSolid& solid);

}  // namespace fieldcast::core
