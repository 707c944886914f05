// checkTiffComplete(): a TIFF whose strips or tiles run past the end of the file was cut short.
// OpenImageIO reads such a striped file "successfully", the missing strips as zeros (it only
// leaves a message behind), so the extent of every strip is checked against the file's length.
#include "ElevationReaders.h"

#include <tiffio.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>

namespace fieldcast::core::detail {

void checkTiffComplete(const std::filesystem::path& path) {
  std::error_code ec;
  const std::uintmax_t fileBytes = std::filesystem::file_size(path, ec);
  if (ec) throw ImportError(path.string() + ": cannot read its size: " + ec.message());
  const TIFFErrorHandler oldWarning = TIFFSetWarningHandler(nullptr);
  std::unique_ptr<TIFF, decltype(&TIFFClose)> tif(TIFFOpen(path.c_str(), "r"), &TIFFClose);
  TIFFSetWarningHandler(oldWarning);
  if (!tif) return;  // not readable by libtiff: OpenImageIO reports it with its own message
  const char* what = TIFFIsTiled(tif.get()) != 0 ? "tiles" : "strips";
  const std::uint32_t count = TIFFNumberOfStrips(tif.get());  // strips or tiles ("striles")
  std::uint32_t firstMissing = count;
  std::uint64_t needed = 0;
  for (std::uint32_t s = 0; s < count; ++s) {
    const std::uint64_t bytes = TIFFGetStrileByteCount(tif.get(), s);
    if (bytes == 0) continue;  // a sparse file's empty block (GDAL SPARSE_OK), not a cut
    const std::uint64_t end = TIFFGetStrileOffset(tif.get(), s) + bytes;
    if (end > fileBytes) {
      firstMissing = std::min(firstMissing, s);
      needed = std::max(needed, end);
    }
  }
  if (firstMissing < count) {
    throw ImportError(path.string() + ": cut short: " + what + " " + std::to_string(firstMissing + 1) + " of " +
                      std::to_string(count) + " onwards lie past the end of the file (" + std::to_string(fileBytes) +
                      " bytes; its data needs " + std::to_string(needed) + "); the file cannot be read whole");
  }
}

}  // namespace fieldcast::core::detail
