// The frame lock's announcements: encode, decode, and the thread that sends and hears them.
#include <io_bridge/FieldLockLink.h>

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <limits>
#include <stdexcept>

namespace fieldcast::io {
namespace {

constexpr std::uint8_t kMagic[4] = {'F', 'C', 'L', 'K'};
constexpr std::uint16_t kVersion = 1;
constexpr std::int64_t kNoneHeard = std::numeric_limits<std::int64_t>::max();
// An epoch further ahead than this is not an instant of this machine's clock (another machine's,
// or garbage): a lock's epoch is its first field, a few hundred milliseconds after its start.
constexpr Nanoseconds kFutureEpochLimit = std::chrono::seconds(10);
// A lock older than this is not one (and field numbers counted from it stay far from overflow).
constexpr Nanoseconds kPastEpochLimit = std::chrono::hours(24 * 365 * 10);

void putBigEndian(std::uint8_t* out, std::uint64_t value, int bytes) noexcept {
  for (int i = bytes - 1; i >= 0; --i, value >>= 8) out[i] = static_cast<std::uint8_t>(value & 0xFFu);
}

std::uint64_t getBigEndian(const std::uint8_t* in, int bytes) noexcept {
  std::uint64_t value = 0;
  for (int i = 0; i < bytes; ++i) value = (value << 8) | in[i];
  return value;
}

std::string describe(const sockaddr_in& a) {
  char text[INET_ADDRSTRLEN] = {};
  inet_ntop(AF_INET, &a.sin_addr, text, sizeof text);
  return std::string(text) + ":" + std::to_string(ntohs(a.sin_port));
}

}  // namespace

std::array<std::uint8_t, kLockAnnouncementBytes> encodeLockAnnouncement(const LockAnnouncement& a) noexcept {
  std::array<std::uint8_t, kLockAnnouncementBytes> out{};
  std::memcpy(out.data(), kMagic, 4);
  putBigEndian(out.data() + 4, kVersion, 2);
  putBigEndian(out.data() + 6, static_cast<std::uint16_t>(a.timeBase), 2);
  putBigEndian(out.data() + 8, static_cast<std::uint64_t>(a.rate.numerator), 4);
  putBigEndian(out.data() + 12, static_cast<std::uint64_t>(a.rate.denominator), 4);
  putBigEndian(out.data() + 16, static_cast<std::uint64_t>(a.epoch.time_since_epoch().count()), 8);
  putBigEndian(out.data() + 24, a.newestField, 8);
  putBigEndian(out.data() + 32, a.senderPid, 4);
  return out;
}

std::optional<LockAnnouncement> decodeLockAnnouncement(std::span<const std::uint8_t> d) noexcept {
  if (d.size() != kLockAnnouncementBytes || std::memcmp(d.data(), kMagic, 4) != 0) return std::nullopt;
  if (getBigEndian(d.data() + 4, 2) != kVersion) return std::nullopt;
  LockAnnouncement a;
  const std::uint64_t timeBase = getBigEndian(d.data() + 6, 2);
  if (timeBase > static_cast<std::uint16_t>(LockTimeBase::Tai)) return std::nullopt;
  a.timeBase = static_cast<LockTimeBase>(timeBase);
  a.rate.numerator = static_cast<std::int64_t>(getBigEndian(d.data() + 8, 4));
  a.rate.denominator = static_cast<std::int64_t>(getBigEndian(d.data() + 12, 4));
  if (a.rate.numerator == 0 || a.rate.denominator == 0) return std::nullopt;
  a.epoch = TimePoint{Nanoseconds{static_cast<std::int64_t>(getBigEndian(d.data() + 16, 8))}};
  a.newestField = getBigEndian(d.data() + 24, 8);
  a.senderPid = static_cast<std::uint32_t>(getBigEndian(d.data() + 32, 4));
  return a;
}

sockaddr_in parseUdpAddress(const std::string& text, const std::string& what) {
  const std::size_t colon = text.rfind(':');
  sockaddr_in a{};
  a.sin_family = AF_INET;
  const std::string host = colon == std::string::npos ? "" : text.substr(0, colon);
  const std::string port = colon == std::string::npos ? "" : text.substr(colon + 1);
  const bool portOk = !port.empty() && port.size() <= 5 &&
                      std::all_of(port.begin(), port.end(), [](char c) { return c >= '0' && c <= '9'; }) &&
                      std::stoi(port) <= 65535;
  if (!portOk || inet_pton(AF_INET, host.c_str(), &a.sin_addr) != 1) {
    throw std::invalid_argument(what + ": expected \"address:port\" (IPv4), got \"" + text + "\"");
  }
  a.sin_port = htons(static_cast<std::uint16_t>(std::stoi(port)));
  return a;
}

FieldLockLink::FieldLockLink(const FieldLockConfig& config, RationalRate rate, const Clock& clock)
    : mRate(rate),
      mTimeBase(config.timeBase),
      mClock(clock),
      mInterval(config.announceInterval),
      mPid(static_cast<std::uint32_t>(::getpid())),
      mEarliestNs(kNoneHeard) {
  sockaddr_in address = parseUdpAddress(config.listen, "lock.listen");
  for (const std::string& peer : config.peers) mPeers.push_back(parseUdpAddress(peer, "lock.peers"));
  mSocket = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (mSocket < 0) throw std::runtime_error("frame lock: socket: " + std::string(std::strerror(errno)));
  if (::bind(mSocket, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    const std::string why = std::strerror(errno);
    ::close(mSocket);
    throw std::runtime_error("frame lock: cannot listen on " + config.listen + ": " + why);
  }
  socklen_t length = sizeof address;
  ::getsockname(mSocket, reinterpret_cast<sockaddr*>(&address), &length);
  mPort = ntohs(address.sin_port);
}

FieldLockLink::~FieldLockLink() {
  stop();
  if (mSocket >= 0) ::close(mSocket);
}

void FieldLockLink::start() {
  if (mThread.joinable()) return;
  mStop.store(false);
  mStarted = mClock.now();
  mThread = std::thread([this] { run(); });
}

void FieldLockLink::awaitPeers() const {
  const TimePoint enough = mStarted + 3 * mInterval;
  while (!earliestEpochHeard() && mClock.now() < enough) std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

void FieldLockLink::stop() {
  mStop.store(true);
  if (mThread.joinable()) mThread.join();
}

std::optional<TimePoint> FieldLockLink::earliestEpochHeard() const noexcept {
  const std::int64_t ns = mEarliestNs.load(std::memory_order_acquire);
  if (ns == kNoneHeard) return std::nullopt;
  return TimePoint{Nanoseconds{ns}};
}

void FieldLockLink::announce(TimePoint epoch, std::uint64_t newestField) noexcept {
  mOwn.store(Own{epoch.time_since_epoch().count(), newestField, true});
}

Nanoseconds FieldLockLink::timeBaseOffset() const noexcept {
  if (mTimeBase == LockTimeBase::Monotonic) return Nanoseconds{0};
  // TAI read between two readings of the service's clock: the offset to well under a microsecond.
  // The tightest of three such readings: a preemption or a stall of the machine between the two
  // would otherwise shift the offset by up to half of it.
  Nanoseconds offset{0};
  Nanoseconds tightest = Nanoseconds::max();
  for (int attempt = 0; attempt < 3; ++attempt) {
    const TimePoint before = mClock.now();
    timespec tai{};
    clock_gettime(CLOCK_TAI, &tai);
    const TimePoint after = mClock.now();
    if (after - before >= tightest) continue;
    tightest = after - before;
    const Nanoseconds taiNs{static_cast<std::int64_t>(tai.tv_sec) * 1'000'000'000 + tai.tv_nsec};
    offset = taiNs - (before.time_since_epoch() + (after - before) / 2);
  }
  return offset;
}

FieldLockCounters FieldLockLink::counters() const noexcept {
  FieldLockCounters c;
  c.sent = mSent.load(std::memory_order_relaxed);
  c.received = mReceived.load(std::memory_order_relaxed);
  c.otherRate = mOtherRate.load(std::memory_order_relaxed);
  c.malformed = mMalformed.load(std::memory_order_relaxed);
  c.strangers = mStrangers.load(std::memory_order_relaxed);
  c.sendErrors = mSendErrors.load(std::memory_order_relaxed);
  return c;
}

void FieldLockLink::run() noexcept {
  TimePoint nextAnnouncement = mClock.now();
  bool announced = false;
  while (!mStop.load(std::memory_order_acquire)) {
    const TimePoint now = mClock.now();
    // The first announcement goes out at once: a channel starting now may be listening for it
    const bool first = !announced && mOwn.load().valid;
    if (now >= nextAnnouncement || first) {
      announced = sendAnnouncement();
      nextAnnouncement = now + mInterval;
    }
    // Wake for the next announcement, and at least every 20 ms to see a stop or a first epoch
    const auto waitMs = std::clamp<std::int64_t>(
        std::chrono::duration_cast<std::chrono::milliseconds>(nextAnnouncement - mClock.now()).count(), 0, 20);
    pollfd fd{mSocket, POLLIN, 0};
    const int ready = ::poll(&fd, 1, static_cast<int>(waitMs));
    if (ready > 0) receiveAll();
  }
}

void FieldLockLink::receiveAll() noexcept {
  std::array<std::uint8_t, 512> buffer{};
  for (;;) {
    sockaddr_in from{};
    socklen_t fromLength = sizeof from;
    const ssize_t bytes =
        ::recvfrom(mSocket, buffer.data(), buffer.size(), 0, reinterpret_cast<sockaddr*>(&from), &fromLength);
    if (bytes < 0) return;  // EAGAIN: all read
    // Only the rig's channels: anyone else could otherwise re-time every channel for good
    const bool peer = std::any_of(mPeers.begin(), mPeers.end(), [&](const sockaddr_in& p) {
      return p.sin_addr.s_addr == from.sin_addr.s_addr && p.sin_port == from.sin_port;
    });
    if (!peer) {
      mStrangers.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    const std::optional<LockAnnouncement> a =
        decodeLockAnnouncement(std::span(buffer.data(), static_cast<std::size_t>(bytes)));
    if (!a) {
      mMalformed.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    if (a->rate.numerator != mRate.numerator || a->rate.denominator != mRate.denominator || a->timeBase != mTimeBase) {
      if (mOtherRate.fetch_add(1, std::memory_order_relaxed) == 0)
        spdlog::warn(
            "frame lock: a channel announces {:.3f} Hz fields on {}, this one makes {:.3f} Hz on {}: not "
            "locked to it",
            a->rate.hz(), a->timeBase == LockTimeBase::Tai ? "CLOCK_TAI" : "CLOCK_MONOTONIC", mRate.hz(),
            mTimeBase == LockTimeBase::Tai ? "CLOCK_TAI" : "CLOCK_MONOTONIC");
      continue;
    }
    const TimePoint epoch = a->epoch - timeBaseOffset();  // on the service's clock
    const TimePoint now = mClock.now();
    if (epoch > now + kFutureEpochLimit || epoch < now - kPastEpochLimit) {
      mMalformed.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    mReceived.fetch_add(1, std::memory_order_relaxed);
    // Earlier by more than the conversion's noise: another lock, the one that began first
    const std::int64_t epochNs = epoch.time_since_epoch().count();
    std::int64_t earliest = mEarliestNs.load(std::memory_order_relaxed);
    while (epochNs < earliest - kSameLockTolerance.count() &&
           !mEarliestNs.compare_exchange_weak(earliest, epochNs, std::memory_order_release)) {
    }
  }
}

bool FieldLockLink::sendAnnouncement() noexcept {
  const Own own = mOwn.load();
  if (!own.valid) return false;
  LockAnnouncement a;
  a.rate = mRate;
  a.timeBase = mTimeBase;
  a.epoch = TimePoint{Nanoseconds{own.epochNs}} + timeBaseOffset();
  a.newestField = own.newestField;
  a.senderPid = mPid;
  const auto bytes = encodeLockAnnouncement(a);
  for (const sockaddr_in& peer : mPeers) {
    const ssize_t sent =
        ::sendto(mSocket, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&peer), sizeof peer);
    if (sent == static_cast<ssize_t>(bytes.size())) {
      mSent.fetch_add(1, std::memory_order_relaxed);
    } else if (mSendErrors.fetch_add(1, std::memory_order_relaxed) == 0) {
      // A peer not running yet refuses on loopback (ECONNREFUSED on a later send): not an error
      spdlog::debug("frame lock: send to {}: {}", describe(peer), std::strerror(errno));
    }
  }
  return true;
}

}  // namespace fieldcast::io
