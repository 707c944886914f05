#pragma once
// The models a placement list can name: the built-in library's (ObjectModels.h) by name, and
// MagicaVoxel .vox files (VoxFile.h; fieldcast-sculpt writes them) by path, relative to the list.

#include <ig_core/ObjectPlacement.h>

#include <filesystem>
#include <map>
#include <memory>
#include <string>

namespace fieldcast::core {

class ModelLibrary {
 public:
  /// Relative .vox paths are found in `baseDir` (the placement list's folder).
  explicit ModelLibrary(std::filesystem::path baseDir);

  /// The model `name` names: built in, or a name ending in ".vox" read from that file (once, then
  /// kept); nullptr for anything else. Throws VoxFileError for a .vox file that cannot be read.
  const VoxelModel* find(const std::string& name);
  /// find() as a placement lookup; the library must outlive it.
  ModelLookup lookup() {
    return [this](const std::string& name) { return find(name); };
  }

 private:
  std::filesystem::path mBaseDir;
  std::map<std::string, std::unique_ptr<VoxelModel>> mFiles;
};

}  // namespace fieldcast::core
