#pragma once
// A POSIX shared-memory ring of the newest fields, for a consumer on the same machine (a
// recorder, an analysis tool, another process's display). One writer, any number of readers;
// readers never block the writer: every slot is a seqlock, a reader copies a slot and keeps the
// copy only if the slot's sequence did not move meanwhile.
//
// Layout of the object (/dev/shm/<name>), native byte order (little-endian on x86-64/arm64),
// every field naturally aligned:
//
//   ShmRingHeader (256 bytes)
//   slot 0: ShmSlotHeader (64 bytes) + field bytes, padded to slotStrideBytes (a multiple of 64)
//   slot 1 …
//
// Publication p (0, 1, 2 … in the order fields were published) is written to slot p % slotCount
// and the slot records p. The header's publishedCount is the number of publications; the newest
// is publishedCount − 1. A slot's sequence is odd while it is
// written and advances by 2 per write. Readers load every shared word atomically (8-byte
// relaxed loads between acquire fences), so a reader racing the writer is well-defined.

#include <io_bridge/FieldSink.h>
#include <io_bridge/StreamFormat.h>

#include <fieldcast/Field.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace fieldcast::io {

/// "FCSTRING": Fieldcast ring. Written last at creation, so a half-made ring never validates.
inline constexpr char kShmRingMagic[8] = {'F', 'C', 'S', 'T', 'R', 'I', 'N', 'G'};
inline constexpr std::uint32_t kShmRingVersion = 1;

/// The ring's header, at offset 0 of the shared object.
struct ShmRingHeader {
  char magic[8];                  ///< kShmRingMagic
  std::uint32_t version;          ///< kShmRingVersion
  std::uint32_t headerBytes;      ///< sizeof(ShmRingHeader) = 256
  std::uint32_t slotCount;        ///< N, 1–1024
  std::uint32_t slotHeaderBytes;  ///< sizeof(ShmSlotHeader) = 64
  std::uint64_t slotStrideBytes;  ///< bytes from one slot to the next (multiple of 64)
  std::uint64_t maxFieldBytes;    ///< room for field pixels in each slot
  std::uint32_t widthPx;          ///< raster width
  std::uint32_t heightPx;         ///< raster height (all rows of a frame)
  std::uint32_t pixelFormat;      ///< 0 grey8, 1 rgb8, 2 uyvy422 (fieldcast::PixelFormat)
  std::uint32_t scan;             ///< 0 progressive, 1 interlaced
  std::uint32_t fieldOrder;       ///< 0 top first, 1 bottom first
  std::uint32_t reserved0;
  std::int64_t fieldRateNumerator;  ///< fields per fieldRateDenominator seconds
  std::int64_t fieldRateDenominator;
  std::int64_t writerPid;
  std::int64_t createdNs;  ///< CLOCK_MONOTONIC, ns
  std::uint64_t reserved1[4];
  std::uint64_t publishedCount;  ///< fields published (atomic; offset 128)
  std::uint64_t reserved2[15];
};
static_assert(sizeof(ShmRingHeader) == 256);

/// The header of one slot, followed by the field's bytes (rows of that field only, top first).
struct ShmSlotHeader {
  std::uint64_t sequence;         ///< odd while being written; +2 per write (atomic)
  std::uint64_t fieldNumber;      ///< k
  std::int64_t displayTimeNs;     ///< t_k on CLOCK_MONOTONIC
  std::int64_t sourcePoseTimeNs;  ///< pose time of the frame it was warped from
  std::uint64_t sourceFrameNumber;
  std::uint32_t parity;  ///< 0 top, 1 bottom, 2 progressive (fieldcast::FieldParity)
  std::uint32_t rows;    ///< rows in this field
  std::uint32_t bytes;   ///< field bytes that follow
  std::uint32_t marginViolations;
  std::uint64_t publication;  ///< p: which publication the slot holds
};
static_assert(sizeof(ShmSlotHeader) == 64);

/// Checks that `bytes` (the first `size` bytes of a mapped ring) hold a ring this code can read:
/// magic, version, sizes, format codes, and that all slots lie inside `size`. Returns an empty
/// string when valid, otherwise what is wrong. Safe on any input.
std::string validateShmRingHeader(const void* bytes, std::size_t size) noexcept;

/// The writer. Creates (replacing a stale one) the shared object on construction and unlinks it
/// on destruction.
class ShmRingWriter {
 public:
  /// Throws std::runtime_error naming the object when it cannot be created or mapped.
  ShmRingWriter(const std::string& name, const StreamFormat& format, int slotCount);
  ~ShmRingWriter();
  ShmRingWriter(const ShmRingWriter&) = delete;
  ShmRingWriter& operator=(const ShmRingWriter&) = delete;

  /// Copies the field into its slot and publishes it. Wait-free, no allocation: RT-safe (may be
  /// called straight from the field thread). Fields that do not match the format are ignored
  /// (returns false).
  bool publish(const Field& field) noexcept;
  const std::string& name() const noexcept { return mName; }
  std::size_t mappedBytes() const noexcept { return mSize; }

 private:
  std::string mName;
  StreamFormat mFormat;
  std::uint8_t* mBase = nullptr;
  std::size_t mSize = 0;
};

/// Outcome of a read.
enum class ShmReadStatus : std::uint8_t {
  Ok,
  NotYet,       ///< nothing published yet, or the requested publication is not out yet
  Overwritten,  ///< the requested publication has been replaced by a newer one
  Busy,         ///< the writer kept rewriting the slot while we copied (retry later)
};

/// A reader, in any process. Never writes to the ring.
class ShmRingReader {
 public:
  /// Maps the ring read-only and validates its header. Throws std::runtime_error naming the
  /// object and the problem (missing, wrong magic or version, truncated).
  explicit ShmRingReader(const std::string& name);
  ~ShmRingReader();
  ShmRingReader(const ShmRingReader&) = delete;
  ShmRingReader& operator=(const ShmRingReader&) = delete;

  /// The stream format recorded by the writer.
  const StreamFormat& format() const noexcept { return mFormat; }
  int slotCount() const noexcept { return mSlotCount; }
  /// Fields published so far. RT-safe.
  std::uint64_t publishedCount() const noexcept;
  /// Copies publication `p` into `out` (resizing its image the first time). Lock-free: never
  /// waits for the writer, retries a few times if the writer rewrites the slot meanwhile.
  ShmReadStatus read(std::uint64_t publication, Field& out) const;
  /// Copies the newest field into `out`.
  ShmReadStatus readLatest(Field& out) const;

 private:
  std::uint8_t* mBase = nullptr;
  std::size_t mSize = 0;
  StreamFormat mFormat;
  int mSlotCount = 0;
  std::size_t mStride = 0;
};

/// ShmRingWriter as a SinkHub sink (for when the field thread should not do the copy itself).
class ShmRingSink final : public FieldSink {
 public:
  ShmRingSink(std::string name, int slotCount) : mName(std::move(name)), mSlots(slotCount) {}
  ~ShmRingSink() override;
  std::string name() const override { return "shm"; }
  void open(const StreamFormat& format) override;
  SinkStatus consume(const Field& field) override;
  void close() override;

 private:
  std::string mName;
  int mSlots;
  std::unique_ptr<ShmRingWriter> mWriter;
};

}  // namespace fieldcast::io
