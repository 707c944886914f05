// The CIGI link's socket and thread: receive, decode, hand over; one Start of Frame per field.
#include <io_bridge/HostLink.h>

#include <arpa/inet.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace fieldcast::io {
namespace {

// Datagrams read per wake before the link serves a pending field: a flood of garbage cannot
// starve the Start of Frame of more than this many decodes (each a few hundred nanoseconds).
constexpr int kMaxDatagramsPerWake = 256;

std::string describe(const HostLinkConfig& c) { return c.listenAddress + ":" + std::to_string(c.port); }

}  // namespace

HostLink::HostLink(const HostLinkConfig& config, Clock& clock, HostHandler& handler)
    : mConfig(config), mClock(clock), mHandler(handler), mReceiveBuffer(cigi::kMaxDatagramBytes) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(config.port);
  if (inet_pton(AF_INET, config.listenAddress.c_str(), &address.sin_addr) != 1) {
    throw std::runtime_error("host link: '" + config.listenAddress + "' is not an IPv4 address");
  }
  mSocket = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (mSocket < 0) throw std::runtime_error("host link: socket: " + std::string(std::strerror(errno)));
  if (::bind(mSocket, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    const std::string why = std::strerror(errno);
    ::close(mSocket);
    throw std::runtime_error("host link: cannot listen on " + describe(config) + ": " + why);
  }
  socklen_t length = sizeof address;
  ::getsockname(mSocket, reinterpret_cast<sockaddr*>(&address), &length);
  mPort = ntohs(address.sin_port);
  mWake = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (mWake < 0) {
    ::close(mSocket);
    throw std::runtime_error("host link: eventfd: " + std::string(std::strerror(errno)));
  }
}

HostLink::~HostLink() {
  stop();
  ::close(mWake);
  ::close(mSocket);
}

void HostLink::start() {
  if (mThread.joinable()) return;
  mStop.store(false);
  mThread = std::thread([this] { run(); });
}

void HostLink::stop() {
  if (!mThread.joinable()) return;
  mStop.store(true);
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t written = ::write(mWake, &one, sizeof one);
  mThread.join();
  publishCounters();
}

void HostLink::fieldStarted(std::uint64_t fieldNumber, TimePoint displayTime, bool renumbered) noexcept {
  if (renumbered) mRenumberedAt.store(fieldNumber, std::memory_order_relaxed);
  if (!mAnnouncedAny) {  // one announcing thread: a plain flag and a relaxed store suffice
    mAnnouncedAny = true;
    mFirstAnnounced.store(fieldNumber, std::memory_order_relaxed);
  }
  mAnnounced.store(FieldAnnouncement{fieldNumber, displayTime});
  mAnnouncementPending.store(true, std::memory_order_release);
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t written = ::write(mWake, &one, sizeof one);
}

void HostLink::run() noexcept {
  if (mConfig.onThreadStart) mConfig.onThreadStart();
  pollfd fds[2] = {{mSocket, POLLIN, 0}, {mWake, POLLIN, 0}};
  while (!mStop.load()) {
    if (::poll(fds, 2, 100) < 0 && errno != EINTR) {
      spdlog::error("host link: poll: {}", std::strerror(errno));
      return;
    }
    if (fds[1].revents & POLLIN) {
      std::uint64_t count = 0;
      [[maybe_unused]] const ssize_t read = ::read(mWake, &count, sizeof count);
    }
    // A pending field first: its Start of Frame is due now, the datagrams can wait a moment.
    if (mAnnouncementPending.load(std::memory_order_acquire)) sendField();
    receiveAll();
    if (mAnnouncementPending.load(std::memory_order_acquire)) sendField();
    publishCounters();
  }
}

void HostLink::receiveAll() {
  for (int k = 0; k < kMaxDatagramsPerWake; ++k) {
    sockaddr_in from{};
    socklen_t fromLength = sizeof from;
    const ssize_t bytes = ::recvfrom(mSocket, mReceiveBuffer.data(), mReceiveBuffer.size(), 0,
                                     reinterpret_cast<sockaddr*>(&from), &fromLength);
    if (bytes < 0) return;  // EAGAIN: drained (other errors: ICMP noise, retried on the next wake)
    const TimePoint arrival = mClock.now();
    ++mCounting.datagramsReceived;
    const cigi::DecodeResult result = mDecoder.decode(
        std::span<const std::uint8_t>(mReceiveBuffer.data(), static_cast<std::size_t>(bytes)), mPackets);
    if (!result) continue;  // counted by the decoder
    mHaveHost = true;
    mHostAddress = from;
    if (mConfig.replyPort != 0) mHostAddress.sin_port = htons(mConfig.replyPort);
    mHandler.onMessage(HostMessage{mPackets, arrival, result.byteSwapped()});
  }
}

void HostLink::sendField() {
  // An exchange, not a store: a plain store may pass the load below (on x86 too), and would then
  // clear a flag raised for a later field after this load had read the earlier one
  mAnnouncementPending.exchange(false, std::memory_order_acq_rel);
  const FieldAnnouncement field = mAnnounced.load();
  // The flag may have been raised again between clearing it and the load, for the field this
  // load already read: served, not to be sent twice. Fields announced but never read (the link
  // was late) are counted here, the one place that sees which fields were served.
  std::uint64_t expected = mServedAny ? mLastServed + 1 : mFirstAnnounced.load(std::memory_order_relaxed);
  // After a move onto another frame lock the numbers jump there: not fields the link lost
  if (const std::uint64_t renumberedAt = mRenumberedAt.exchange(0, std::memory_order_relaxed); renumberedAt != 0)
    expected = std::max(expected, renumberedAt);
  if (mServedAny && field.fieldNumber <= mLastServed) return;
  if (field.fieldNumber > expected) mCounting.fieldsCoalesced += field.fieldNumber - expected;
  mServedAny = true;
  mLastServed = field.fieldNumber;
  if (!mHandler.onField(field, mOut)) return;
  if (!mHaveHost) {
    ++mCounting.fieldsWithoutHost;
    return;
  }
  const std::span<const std::uint8_t> bytes = mOut.bytes();
  if (::sendto(mSocket, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&mHostAddress),
               sizeof mHostAddress) < 0) {
    if (mCounting.sendErrors++ == 0) spdlog::warn("host link: sending to the host: {}", std::strerror(errno));
    return;
  }
  ++mCounting.messagesSent;
}

void HostLink::publishCounters() {
  const cigi::DecodeCounters& d = mDecoder.counters();
  mCounting.datagramsAccepted = d.datagramsAccepted;
  mCounting.datagramsByteSwapped = d.datagramsByteSwapped;
  mCounting.datagramsRejected = d.rejectedTotal();
  mCounting.rejectedByReason = d.datagramsRejected;
  mCounting.packetsSkipped = d.packetsSkipped;
  const std::lock_guard lock(mCountersMutex);
  mPublished = mCounting;
}

HostLinkCounters HostLink::counters() const noexcept {
  const std::lock_guard lock(mCountersMutex);
  return mPublished;
}

}  // namespace fieldcast::io
