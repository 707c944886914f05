#include "ImageWrite.h"

#include <stdexcept>
#include <string>

namespace fieldcast::io {

void writeImage(const std::filesystem::path& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                const void* pixels) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) throw std::runtime_error(path.string() + ": no image writer for this extension: " + OIIO::geterror());
  // Encode on this (the sink's) thread only: an IG's cores belong to the renderer.
  out->threads(1);
  if (!out->open(path.string(), spec) || !out->write_image(type, pixels) || !out->close()) {
    throw std::runtime_error(path.string() + ": " + out->geterror());
  }
}

}  // namespace fieldcast::io
