// libFuzzer target: the shared-memory ring header a reader maps comes from another process, so
// its validation must be safe on any bytes, and whatever it accepts must describe slots that lie
// inside the mapping.

#include <io_bridge/ShmRing.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fieldcast::io;
  // The mapping is at least as large as the input; let the input also claim a larger mapping.
  const std::string problem = validateShmRingHeader(size ? data : nullptr, size);
  if (!problem.empty()) return 0;
  ShmRingHeader h;
  std::memcpy(&h, data, sizeof h);
  // Slot by slot, so a stride that would wrap the product cannot hide past the end
  std::uint64_t end = sizeof(ShmRingHeader);
  for (std::uint32_t k = 0; k < h.slotCount; ++k) {
    if (h.slotStrideBytes > size || end > size - h.slotStrideBytes) std::abort();
    end += h.slotStrideBytes;
  }
  if (h.slotStrideBytes < sizeof(ShmSlotHeader) + h.maxFieldBytes) std::abort();
  return 0;
}
