#pragma once
// The one image writer of the sinks: OpenImageIO, the format chosen by the file's extension.

#include <OpenImageIO/imageio.h>

#include <filesystem>

namespace fieldcast::io {

/// Writes `pixels` (interleaved, `type` per channel, `spec`'s size) to `path` on the calling
/// thread only. Throws std::runtime_error naming the path with OpenImageIO's message.
void writeImage(const std::filesystem::path& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                const void* pixels);

}  // namespace fieldcast::io
