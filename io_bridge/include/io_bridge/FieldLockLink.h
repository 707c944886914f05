#pragma once
// The software frame lock between channels (README "Channels"): every channel announces its
// lock — the display time of its field 0 (the epoch) on the machine's CLOCK_MONOTONIC, and the
// field rate — to the other channels over UDP, ten times a second, and listens for theirs. The
// earliest epoch wins: a channel that hears an earlier one than its own moves its field clock
// onto it, so all channels number their fields alike and show field k at the same instant, and
// a channel restarted late takes the lock the others hold. Nobody waits for anybody: a channel
// that falls behind misses its own fields only. The epochs are instants of one clock: the
// machine's CLOCK_MONOTONIC holds the lock for channels on one machine; CLOCK_TAI holds it across
// machines whose clocks are disciplined to one time base (PTP: ptp4l and phc2sys), the link
// converting between it and the service's CLOCK_MONOTONIC at every announcement.
//
// The announcement, 40 bytes, big-endian:
//   0 "FCLK"   4 version (u16) = 1   6 time base (u16: 0 CLOCK_MONOTONIC, 1 CLOCK_TAI)
//   8 rate numerator (u32)   12 rate denominator (u32)   16 epoch, ns of the time base (i64)
//   24 newest field made (u64)   32 sender pid (u32)   36 reserved (u32)

#include <fieldcast/SeqLock.h>
#include <fieldcast/Time.h>

#include <netinet/in.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace fieldcast::io {

/// The clock a lock's epochs are instants of.
enum class LockTimeBase : std::uint16_t {
  Monotonic = 0,  ///< CLOCK_MONOTONIC: channels on one machine
  Tai = 1,        ///< CLOCK_TAI: channels on machines whose clocks one PTP grandmaster disciplines
};

/// Epochs closer than this are one lock: what converting between two clocks costs in precision.
inline constexpr Nanoseconds kSameLockTolerance{std::chrono::microseconds(100)};

/// Where a channel listens for the others' announcements and where it sends its own.
struct FieldLockConfig {
  std::string listen;              ///< "address:port" of this channel; empty: no software lock
  std::vector<std::string> peers;  ///< "address:port" of each other channel
  LockTimeBase timeBase = LockTimeBase::Monotonic;
  Nanoseconds announceInterval{std::chrono::milliseconds(100)};
};

/// One channel's lock, as announced.
struct LockAnnouncement {
  RationalRate rate;
  LockTimeBase timeBase = LockTimeBase::Monotonic;
  TimePoint epoch{};              ///< display time of field 0, an instant of `timeBase`
  std::uint64_t newestField = 0;  ///< the newest field the sender made (for a person reading a capture)
  std::uint32_t senderPid = 0;
};

inline constexpr std::size_t kLockAnnouncementBytes = 40;
std::array<std::uint8_t, kLockAnnouncementBytes> encodeLockAnnouncement(const LockAnnouncement& a) noexcept;
/// Empty when the datagram is not a version-1 announcement (size, magic, version, a zero rate,
/// an unknown time base).
std::optional<LockAnnouncement> decodeLockAnnouncement(std::span<const std::uint8_t> datagram) noexcept;

/// Parses "a.b.c.d:port" (IPv4, port 0–65535). Throws std::invalid_argument naming `what`.
sockaddr_in parseUdpAddress(const std::string& text, const std::string& what);

/// Figures of the link. Read from any thread.
struct FieldLockCounters {
  std::uint64_t sent = 0;
  std::uint64_t received = 0;   ///< announcements accepted
  std::uint64_t otherRate = 0;  ///< announcements of another field rate: not this lock
  std::uint64_t malformed = 0;  ///< datagrams that are not announcements, or epochs not on this clock
  std::uint64_t strangers = 0;  ///< datagrams from an address that is not one of the peers: ignored
  std::uint64_t sendErrors = 0;
};

class FieldLockLink {
 public:
  /// Binds `config.listen` and resolves the peers. `clock` is the service's: CLOCK_MONOTONIC
  /// (SystemClock) when the time base is TAI, which is read beside it. Throws std::runtime_error /
  /// invalid_argument naming the address on failure.
  FieldLockLink(const FieldLockConfig& config, RationalRate rate, const Clock& clock);
  ~FieldLockLink();
  FieldLockLink(const FieldLockLink&) = delete;
  FieldLockLink& operator=(const FieldLockLink&) = delete;

  /// Starts the thread that announces (once announce() was called) and listens.
  void start();
  void stop();
  std::uint16_t port() const noexcept { return mPort; }

  /// Blocks until a peer's announcement has been heard or the link has listened for three
  /// announcement intervals since start(): a channel starting beside running ones joins their
  /// lock instead of beginning its own. Not RT-safe (before the fields start).
  void awaitPeers() const;

  /// The earliest epoch a peer of this field rate and time base has announced, on `clock`; empty
  /// when none was heard. Wait-free, RT-safe.
  std::optional<TimePoint> earliestEpochHeard() const noexcept;
  /// What this channel announces from now on (`epoch` on `clock`). Wait-free, RT-safe (the field
  /// thread).
  void announce(TimePoint epoch, std::uint64_t newestField) noexcept;

  FieldLockCounters counters() const noexcept;

 private:
  void run() noexcept;
  void receiveAll() noexcept;
  bool sendAnnouncement() noexcept;  // false: nothing to announce yet

  struct Own {
    std::int64_t epochNs = 0;
    std::uint64_t newestField = 0;
    bool valid = false;
  };

  /// The time base's instant minus the service clock's, now (0 for CLOCK_MONOTONIC).
  Nanoseconds timeBaseOffset() const noexcept;

  RationalRate mRate;
  LockTimeBase mTimeBase;
  const Clock& mClock;
  Nanoseconds mInterval;
  std::vector<sockaddr_in> mPeers;
  int mSocket = -1;
  std::uint16_t mPort = 0;
  std::uint32_t mPid = 0;
  SeqLock<Own> mOwn;
  std::atomic<std::int64_t> mEarliestNs;  // INT64_MAX: none heard
  TimePoint mStarted{};
  std::atomic<bool> mStop{false};
  std::thread mThread;
  std::atomic<std::uint64_t> mSent{0}, mReceived{0}, mOtherRate{0}, mMalformed{0}, mStrangers{0}, mSendErrors{0};
};

}  // namespace fieldcast::io
