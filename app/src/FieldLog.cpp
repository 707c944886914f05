#include "FieldLog.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace fieldcast::app {
namespace {

constexpr auto kDrainInterval = std::chrono::milliseconds{50};
constexpr const char* kHeader =
    "field,display_ns,emitted_ns,x_east_m,y_north_m,z_up_m,heading_deg,pitch_deg,roll_deg,frame,frame_pose_ns,"
    "black,margin_px,host_frame,host_arrival_ns\n";

}  // namespace

FieldLog::FieldLog(const std::filesystem::path& path, std::size_t capacity, bool startWriter)
    : mPath(path), mRing(std::make_unique<FieldRecord[]>(std::bit_ceil(std::max<std::size_t>(capacity, 2)))) {
  mMask = std::bit_ceil(std::max<std::size_t>(capacity, 2)) - 1;
  std::error_code error;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), error);
  mFile = std::fopen(path.c_str(), "w");
  if (mFile == nullptr || std::fputs(kHeader, mFile) < 0 || std::fflush(mFile) != 0) {
    const std::string reason = std::strerror(errno);
    if (mFile != nullptr) std::fclose(mFile);
    throw std::runtime_error("metrics.field_log: cannot write " + path.string() + ": " + reason);
  }
  if (startWriter) mWriter = std::thread([this] { writerMain(); });
}

FieldLog::~FieldLog() {
  try {
    stop();
  } catch (...) {  // the service reports a failed write from its own stop()
  }
}

bool FieldLog::push(const FieldRecord& record) noexcept {
  const std::uint64_t head = mHead.load(std::memory_order_relaxed);
  if (head - mTail.load(std::memory_order_acquire) > mMask) {
    mDropped.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  mRing[head & mMask] = record;
  mHead.store(head + 1, std::memory_order_release);
  return true;
}

void FieldLog::drain() noexcept {
  const std::uint64_t head = mHead.load(std::memory_order_acquire);
  std::uint64_t tail = mTail.load(std::memory_order_relaxed);
  for (; tail != head; ++tail) {
    const FieldRecord& r = mRing[tail & mMask];
    int n = std::fprintf(mFile,
                         "%" PRIu64 ",%" PRId64 ",%" PRId64 ",%.4f,%.4f,%.4f,%.6f,%.6f,%.6f,%" PRIu64 ",%" PRId64
                         ",%d,%" PRIu32 ",",
                         r.fieldNumber, r.displayNs, r.emittedNs, r.pose.positionM.x, r.pose.positionM.y,
                         r.pose.positionM.z, degrees(r.pose.headingRad), degrees(r.pose.pitchRad),
                         degrees(r.pose.rollRad), r.frameNumber, r.framePoseNs, r.black ? 1 : 0, r.marginPx);
    if (n >= 0) {
      n = r.hasHostSample ? std::fprintf(mFile, "%" PRIu32 ",%" PRId64 "\n", r.hostFrame, r.hostArrivalNs)
                          : std::fputs(",\n", mFile);
    }
    if (n < 0) mWriteFailed = true;
    mTail.store(tail + 1, std::memory_order_release);  // the slot is free again
    mWritten.fetch_add(1, std::memory_order_relaxed);
  }
  if (std::fflush(mFile) != 0) mWriteFailed = true;
}

void FieldLog::writerMain() noexcept {
  std::unique_lock lock(mWakeMutex);
  while (!mStopping) {
    mWake.wait_for(lock, kDrainInterval, [this] { return mStopping; });
    lock.unlock();
    drain();
    lock.lock();
  }
}

void FieldLog::stop() {
  if (mStopped) return;
  mStopped = true;
  {
    const std::lock_guard lock(mWakeMutex);
    mStopping = true;
  }
  mWake.notify_all();
  if (mWriter.joinable()) mWriter.join();
  drain();  // what came after the writer's last pass
  const bool closed = std::fclose(mFile) == 0;
  mFile = nullptr;
  if (mWriteFailed || !closed) throw std::runtime_error("metrics.field_log: cannot write " + mPath.string());
}

}  // namespace fieldcast::app
