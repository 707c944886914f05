#pragma once
// The per-field record (metrics.field_log): one CSV line per emitted field — its number, display
// and emission instants, the pose it was warped to, the frame it was warped from and, with a host,
// the host sample that pose was made from. The field thread pushes into a preallocated
// single-producer ring (wait-free, no allocation); a writer thread drains it to the file every
// 50 ms. A full ring drops the record and counts it. Columns: config/README.md, "[metrics]".

#include <fieldcast/Pose.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <thread>

namespace fieldcast::app {

/// One emitted field. Instants are CLOCK_MONOTONIC nanoseconds.
struct FieldRecord {
  std::uint64_t fieldNumber = 0;
  std::int64_t displayNs = 0;      ///< the field's display time
  std::int64_t emittedNs = 0;      ///< when it was handed to the sinks
  Pose pose;                       ///< the pose it was warped to (the channel's eye: ownship + view offset)
  std::uint64_t frameNumber = 0;   ///< the frame it was warped from (0: none yet)
  std::int64_t framePoseNs = 0;    ///< that frame's pose time (0: none)
  bool black = false;              ///< no usable frame: the field is black
  std::uint32_t marginPx = 0;      ///< its pixels sampled outside what the frame rendered (margin violations)
  bool hasHostSample = false;      ///< motion.source = "host" and a sample had arrived
  std::uint32_t hostFrame = 0;     ///< the newest host sample the pose was made from: its host frame number ...
  std::int64_t hostArrivalNs = 0;  ///< ... and when its datagram arrived at the IG
};

class FieldLog {
 public:
  /// Room for 68 s of 60 Hz fields: the writer would have to stall that long to drop one.
  static constexpr std::size_t kDefaultCapacity = 4096;

  /// Creates (truncates) `path` and writes the header line; starts the writer thread unless
  /// `startWriter` is false (tests drain with stop()). Throws std::runtime_error naming
  /// metrics.field_log and the path when it cannot be written. `capacity` is rounded up to a power of 2.
  explicit FieldLog(const std::filesystem::path& path, std::size_t capacity = kDefaultCapacity,
                    bool startWriter = true);
  ~FieldLog();
  FieldLog(const FieldLog&) = delete;
  FieldLog& operator=(const FieldLog&) = delete;

  /// Queues one record. One producer thread (the field thread); wait-free, RT-safe. False when
  /// the ring is full: the record is dropped and counted.
  bool push(const FieldRecord& record) noexcept;

  /// Stops the writer, writes what is queued and closes the file. Idempotent. Throws
  /// std::runtime_error when the file could not be written.
  void stop();

  std::uint64_t written() const noexcept { return mWritten.load(std::memory_order_relaxed); }
  std::uint64_t dropped() const noexcept { return mDropped.load(std::memory_order_relaxed); }
  const std::filesystem::path& path() const noexcept { return mPath; }

 private:
  void writerMain() noexcept;
  void drain() noexcept;  // writer side: everything queued so far to the file

  std::filesystem::path mPath;
  std::FILE* mFile = nullptr;
  std::unique_ptr<FieldRecord[]> mRing;
  std::size_t mMask = 0;
  alignas(64) std::atomic<std::uint64_t> mHead{0};  // next slot the producer fills
  alignas(64) std::atomic<std::uint64_t> mTail{0};  // next slot the writer reads
  std::atomic<std::uint64_t> mWritten{0};
  std::atomic<std::uint64_t> mDropped{0};
  bool mWriteFailed = false;  // writer side
  std::mutex mWakeMutex;      // the writer's sleep only: the producer never takes it
  std::condition_variable mWake;
  bool mStopping = false;
  bool mStopped = false;
  std::thread mWriter;
};

}  // namespace fieldcast::app
