#include <ig_core/ModelLibrary.h>
#include <ig_core/VoxFile.h>

#include <utility>

namespace fieldcast::core {

ModelLibrary::ModelLibrary(std::filesystem::path baseDir) : mBaseDir(std::move(baseDir)) {}

const VoxelModel* ModelLibrary::find(const std::string& name) {
  if (const VoxelModel* builtin = findBuiltinModel(name)) return builtin;
  if (name.size() <= 4 || name.compare(name.size() - 4, 4, ".vox") != 0) return nullptr;
  auto it = mFiles.find(name);
  if (it == mFiles.end()) {
    const std::filesystem::path path = mBaseDir / name;  // an absolute name stays itself
    VoxelModel model = toVoxelModel(readVoxFile(path), name);
    it = mFiles.emplace(name, std::make_unique<VoxelModel>(std::move(model))).first;
  }
  return it->second.get();
}

}  // namespace fieldcast::core
