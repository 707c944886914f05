// Shared-memory ring: per-slot seqlocks (Lameter, "Effective synchronization on Linux/NUMA
// systems", 2005; the same protocol as fieldcast::SeqLock) over a POSIX shm object. Every shared
// word is accessed with __atomic builtins so readers racing the writer are data-race free.

#include <io_bridge/ShmRing.h>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace fieldcast::io {

static_assert(std::endian::native == std::endian::little, "the shm ring layout packs 32-bit pairs little-endian");

namespace {

constexpr std::size_t kPublishedCountOffset = 128;
constexpr int kMaxSlots = 1024;
constexpr int kReadAttempts = 4;

std::uint64_t loadRelaxed(const std::uint8_t* p) noexcept {
  return __atomic_load_n(reinterpret_cast<const std::uint64_t*>(p), __ATOMIC_RELAXED);
}
std::uint64_t loadAcquire(const std::uint8_t* p) noexcept {
  return __atomic_load_n(reinterpret_cast<const std::uint64_t*>(p), __ATOMIC_ACQUIRE);
}
void storeRelaxed(std::uint8_t* p, std::uint64_t v) noexcept {
  __atomic_store_n(reinterpret_cast<std::uint64_t*>(p), v, __ATOMIC_RELAXED);
}
void storeRelease(std::uint8_t* p, std::uint64_t v) noexcept {
  __atomic_store_n(reinterpret_cast<std::uint64_t*>(p), v, __ATOMIC_RELEASE);
}

std::size_t roundUp(std::size_t v, std::size_t to) noexcept { return (v + to - 1) / to * to; }

std::size_t maxRowsOf(const StreamFormat& f) noexcept {
  return static_cast<std::size_t>(
      f.fieldRows(f.scan == ScanMode::Progressive ? FieldParity::Progressive : FieldParity::Top));
}

}  // namespace

std::string validateShmRingHeader(const void* bytes, std::size_t size) noexcept {
  if (bytes == nullptr || size < sizeof(ShmRingHeader)) return "smaller than the 256-byte header";
  ShmRingHeader h;
  std::memcpy(&h, bytes, sizeof h);
  if (std::memcmp(h.magic, kShmRingMagic, sizeof h.magic) != 0) return "not a Fieldcast ring (bad magic)";
  if (h.version != kShmRingVersion) return "ring version " + std::to_string(h.version) + ", this reader knows 1";
  if (h.headerBytes != sizeof(ShmRingHeader) || h.slotHeaderBytes != sizeof(ShmSlotHeader))
    return "header sizes differ";
  if (h.slotCount < 1 || h.slotCount > kMaxSlots)
    return "slot count " + std::to_string(h.slotCount) + " outside 1..1024";
  if (h.widthPx < 1 || h.widthPx > 16384 || h.heightPx < 1 || h.heightPx > 16384) return "raster size out of range";
  if (h.pixelFormat > 2 || h.scan > 1 || h.fieldOrder > 1) return "unknown pixel format, scan or field order code";
  if (h.fieldRateNumerator <= 0 || h.fieldRateDenominator <= 0) return "field rate not positive";
  const auto format = static_cast<PixelFormat>(h.pixelFormat);
  if (format == PixelFormat::Uyvy422 && h.widthPx % 2 != 0) return "odd width for uyvy422";
  const std::size_t rows = h.scan == 1 ? (h.heightPx + 1) / 2 : h.heightPx;
  if (h.maxFieldBytes != rowBytes(format, static_cast<int>(h.widthPx)) * rows)
    return "field size does not match raster";
  if (h.slotStrideBytes % 64 != 0 || h.slotStrideBytes < sizeof(ShmSlotHeader) + roundUp(h.maxFieldBytes, 8)) {
    return "slot stride too small or unaligned";
  }
  // The stride is bounded below only: held against the mapping by a division, since stride × slots
  // could wrap past 2^64 (2^63 × 2 is 0) and pass
  if (h.slotStrideBytes > (size - sizeof(ShmRingHeader)) / h.slotCount) {
    return "truncated: " + std::to_string(size) + " bytes, too few for " + std::to_string(h.slotCount) + " slots of " +
           std::to_string(h.slotStrideBytes) + " bytes";
  }
  return {};
}

// ---------------------------------------------------------------------------------------------
ShmRingWriter::ShmRingWriter(const std::string& name, const StreamFormat& format, int slotCount)
    : mName(name), mFormat(format) {
  format.validate();
  if (slotCount < 1 || slotCount > kMaxSlots) throw std::invalid_argument("shm ring: slots must be 1..1024");
  const std::size_t maxBytes = rowBytes(format.pixelFormat, format.widthPx) * maxRowsOf(format);
  const std::size_t stride = roundUp(sizeof(ShmSlotHeader) + roundUp(maxBytes, 8), 64);
  mSize = sizeof(ShmRingHeader) + stride * static_cast<std::size_t>(slotCount);

  // A ring left by a crashed run is replaced: readers of the old one keep their mapping.
  shm_unlink(name.c_str());
  const int fd = shm_open(name.c_str(), O_CREAT | O_EXCL | O_RDWR | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("shm ring " + name + ": cannot create: " + std::strerror(errno));
  if (ftruncate(fd, static_cast<off_t>(mSize)) != 0) {
    const int e = errno;
    ::close(fd);
    shm_unlink(name.c_str());
    throw std::runtime_error("shm ring " + name + ": cannot size to " + std::to_string(mSize) +
                             " bytes: " + std::strerror(e));
  }
  void* p = mmap(nullptr, mSize, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  ::close(fd);
  if (p == MAP_FAILED) {
    shm_unlink(name.c_str());
    throw std::runtime_error("shm ring " + name + ": mmap failed: " + std::strerror(errno));
  }
  mBase = static_cast<std::uint8_t*>(p);

  ShmRingHeader h{};
  h.version = kShmRingVersion;
  h.headerBytes = sizeof(ShmRingHeader);
  h.slotCount = static_cast<std::uint32_t>(slotCount);
  h.slotHeaderBytes = sizeof(ShmSlotHeader);
  h.slotStrideBytes = stride;
  h.maxFieldBytes = maxBytes;
  h.widthPx = static_cast<std::uint32_t>(format.widthPx);
  h.heightPx = static_cast<std::uint32_t>(format.heightPx);
  h.pixelFormat = static_cast<std::uint32_t>(format.pixelFormat);
  h.scan = format.scan == ScanMode::Interlaced ? 1u : 0u;
  h.fieldOrder = format.fieldOrder == FieldOrder::BottomFirst ? 1u : 0u;
  h.fieldRateNumerator = format.fieldRate.numerator;
  h.fieldRateDenominator = format.fieldRate.denominator;
  h.writerPid = getpid();
  h.createdNs = MonotonicClock::now().time_since_epoch().count();
  std::memcpy(mBase, &h, sizeof h);  // magic still zero: not valid yet
  std::atomic_thread_fence(std::memory_order_release);
  std::uint64_t magic;
  std::memcpy(&magic, kShmRingMagic, 8);
  storeRelease(mBase, magic);
}

ShmRingWriter::~ShmRingWriter() {
  if (mBase) munmap(mBase, mSize);
  shm_unlink(mName.c_str());
}

bool ShmRingWriter::publish(const Field& field) noexcept {
  if (!mFormat.accepts(field)) return false;
  const auto* h = reinterpret_cast<const ShmRingHeader*>(mBase);
  const std::uint64_t p = loadRelaxed(mBase + kPublishedCountOffset);
  std::uint8_t* slot = mBase + sizeof(ShmRingHeader) + (p % h->slotCount) * h->slotStrideBytes;

  const std::uint64_t seq = loadRelaxed(slot);
  storeRelaxed(slot, seq + 1);  // odd: the slot is being written
  std::atomic_thread_fence(std::memory_order_release);
  const auto bytes = field.image.bytes();
  storeRelaxed(slot + 8, field.fieldNumber);
  storeRelaxed(slot + 16, static_cast<std::uint64_t>(field.displayTime.time_since_epoch().count()));
  storeRelaxed(slot + 24, static_cast<std::uint64_t>(field.sourcePoseTime.time_since_epoch().count()));
  storeRelaxed(slot + 32, field.sourceFrameNumber);
  storeRelaxed(slot + 40,
               static_cast<std::uint64_t>(field.parity) | (static_cast<std::uint64_t>(field.image.heightPx()) << 32));
  storeRelaxed(slot + 48, bytes.size() | (static_cast<std::uint64_t>(field.marginViolations) << 32));
  storeRelaxed(slot + 56, p);
  // Field bytes as 64-bit words (the slot has room for the rounded-up tail)
  std::uint8_t* data = slot + sizeof(ShmSlotHeader);
  const std::size_t whole = bytes.size() / 8 * 8;
  for (std::size_t i = 0; i < whole; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, bytes.data() + i, 8);
    storeRelaxed(data + i, w);
  }
  if (whole < bytes.size()) {
    std::uint64_t w = 0;
    std::memcpy(&w, bytes.data() + whole, bytes.size() - whole);
    storeRelaxed(data + whole, w);
  }
  storeRelease(slot, seq + 2);
  storeRelease(mBase + kPublishedCountOffset, p + 1);
  return true;
}

// ---------------------------------------------------------------------------------------------
ShmRingReader::ShmRingReader(const std::string& name) {
  const int fd = shm_open(name.c_str(), O_RDONLY | O_CLOEXEC, 0);
  if (fd < 0) {
    throw std::runtime_error("shm ring " + name + ": cannot open: " + std::strerror(errno) +
                             (errno == ENOENT ? " (is the service running with sinks.shm.enabled?)" : ""));
  }
  struct stat st {};
  if (fstat(fd, &st) != 0 || st.st_size < static_cast<off_t>(sizeof(ShmRingHeader))) {
    ::close(fd);
    throw std::runtime_error("shm ring " + name + ": too small to be a ring");
  }
  mSize = static_cast<std::size_t>(st.st_size);
  void* p = mmap(nullptr, mSize, PROT_READ, MAP_SHARED, fd, 0);
  ::close(fd);
  if (p == MAP_FAILED) throw std::runtime_error("shm ring " + name + ": mmap failed: " + std::strerror(errno));
  mBase = static_cast<std::uint8_t*>(p);
  // Copy the header word by word (publishedCount moves under us), then validate the copy.
  alignas(8) std::uint8_t copy[sizeof(ShmRingHeader)];
  for (std::size_t i = 0; i < sizeof copy; i += 8) {
    const std::uint64_t w = i == 0 ? loadAcquire(mBase) : loadRelaxed(mBase + i);  // magic first
    std::memcpy(copy + i, &w, 8);
  }
  const std::string problem = validateShmRingHeader(copy, mSize);
  if (!problem.empty()) {
    munmap(mBase, mSize);
    mBase = nullptr;
    throw std::runtime_error("shm ring " + name + ": " + problem);
  }
  ShmRingHeader h;
  std::memcpy(&h, copy, sizeof h);
  mFormat.widthPx = static_cast<int>(h.widthPx);
  mFormat.heightPx = static_cast<int>(h.heightPx);
  mFormat.pixelFormat = static_cast<PixelFormat>(h.pixelFormat);
  mFormat.scan = h.scan ? ScanMode::Interlaced : ScanMode::Progressive;
  mFormat.fieldOrder = h.fieldOrder ? FieldOrder::BottomFirst : FieldOrder::TopFirst;
  mFormat.fieldRate = RationalRate{h.fieldRateNumerator, h.fieldRateDenominator};
  mFormat.pixelAspect = defaultPixelAspect(mFormat.widthPx, mFormat.heightPx);
  mSlotCount = static_cast<int>(h.slotCount);
  mStride = h.slotStrideBytes;
}

ShmRingReader::~ShmRingReader() {
  if (mBase) munmap(mBase, mSize);
}

std::uint64_t ShmRingReader::publishedCount() const noexcept { return loadAcquire(mBase + kPublishedCountOffset); }

ShmReadStatus ShmRingReader::read(std::uint64_t publication, Field& out) const {
  if (publication >= publishedCount()) return ShmReadStatus::NotYet;
  const std::uint8_t* slot =
      mBase + sizeof(ShmRingHeader) + (publication % static_cast<std::uint64_t>(mSlotCount)) * mStride;
  const std::size_t maxBytes = rowBytes(mFormat.pixelFormat, mFormat.widthPx) * maxRowsOf(mFormat);
  for (int attempt = 0; attempt < kReadAttempts; ++attempt) {
    const std::uint64_t before = loadAcquire(slot);
    if (before & 1u) continue;  // being written right now
    const std::uint64_t held = loadRelaxed(slot + 56);
    const std::uint64_t shape = loadRelaxed(slot + 40);
    const std::uint64_t sizes = loadRelaxed(slot + 48);
    const auto parity = static_cast<std::uint32_t>(shape & 0xffffffffu);
    const auto rows = static_cast<int>(shape >> 32);
    const std::size_t bytes = sizes & 0xffffffffu;
    if (held != publication) {
      std::atomic_thread_fence(std::memory_order_acquire);
      if (loadRelaxed(slot) != before) continue;
      return held > publication ? ShmReadStatus::Overwritten : ShmReadStatus::NotYet;
    }
    // A torn read can show any numbers: check them before using them as sizes
    if (parity > 2 || rows < 0 || rows > mFormat.heightPx || bytes > maxBytes ||
        bytes != rowBytes(mFormat.pixelFormat, mFormat.widthPx) * static_cast<std::size_t>(rows)) {
      continue;
    }
    if (out.image.widthPx() != mFormat.widthPx || out.image.heightPx() != rows ||
        out.image.format() != mFormat.pixelFormat) {
      out.image.resize(mFormat.widthPx, rows, mFormat.pixelFormat);
    }
    std::uint8_t* dst = out.image.bytes().data();
    const std::uint8_t* data = slot + sizeof(ShmSlotHeader);
    const std::size_t whole = bytes / 8 * 8;
    for (std::size_t i = 0; i < whole; i += 8) {
      const std::uint64_t w = loadRelaxed(data + i);
      std::memcpy(dst + i, &w, 8);
    }
    if (whole < bytes) {
      const std::uint64_t w = loadRelaxed(data + whole);
      std::memcpy(dst + whole, &w, bytes - whole);
    }
    out.fieldNumber = loadRelaxed(slot + 8);
    out.displayTime = TimePoint{Nanoseconds{static_cast<std::int64_t>(loadRelaxed(slot + 16))}};
    out.sourcePoseTime = TimePoint{Nanoseconds{static_cast<std::int64_t>(loadRelaxed(slot + 24))}};
    out.sourceFrameNumber = loadRelaxed(slot + 32);
    out.marginViolations = static_cast<std::uint32_t>(sizes >> 32);
    out.parity = static_cast<FieldParity>(parity);
    out.rasterHeightPx = mFormat.heightPx;
    std::atomic_thread_fence(std::memory_order_acquire);
    if (loadRelaxed(slot) == before) return ShmReadStatus::Ok;
  }
  return ShmReadStatus::Busy;
}

ShmReadStatus ShmRingReader::readLatest(Field& out) const {
  const std::uint64_t count = publishedCount();
  if (count == 0) return ShmReadStatus::NotYet;
  return read(count - 1, out);
}

// ---------------------------------------------------------------------------------------------
ShmRingSink::~ShmRingSink() = default;

void ShmRingSink::open(const StreamFormat& format) { mWriter = std::make_unique<ShmRingWriter>(mName, format, mSlots); }

SinkStatus ShmRingSink::consume(const Field& field) {
  mWriter->publish(field);
  return SinkStatus::Ok;
}

void ShmRingSink::close() { mWriter.reset(); }

}  // namespace fieldcast::io
