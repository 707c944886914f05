// The frame lock's announcements on loopback: the wire format, the earliest epoch winning, and
// what is not a lock of this channel (another rate, not an announcement, not this clock's).
#include <io_bridge/FieldLockLink.h>

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <ctime>

#include "../../../tests/common/FreePort.h"

#include <gtest/gtest.h>

#include <thread>

namespace fieldcast::io {
namespace {

using namespace std::chrono_literals;
using fieldcast::testing::freePort;

const RationalRate kNtsc{60000, 1001};

std::string loopback(std::uint16_t port) { return "127.0.0.1:" + std::to_string(port); }

// Waits up to 3 s for `done`.
template <typename Done>
bool within3s(Done done) {
  for (int i = 0; i < 300 && !done(); ++i) std::this_thread::sleep_for(10ms);
  return done();
}

TEST(FieldLockLink, AnAnnouncementIsFortyBigEndianBytesAndReadsBack) {
  LockAnnouncement a;
  a.rate = kNtsc;
  a.epoch = TimePoint{Nanoseconds{0x0102030405060708}};
  a.newestField = 4242;
  a.senderPid = 77;
  const auto bytes = encodeLockAnnouncement(a);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "FCLK");
  EXPECT_EQ(bytes[5], 1);      // version 1, big-endian
  EXPECT_EQ(bytes[10], 0xEA);  // 60000 = 0x0000EA60
  EXPECT_EQ(bytes[16], 0x01);  // the epoch's most significant byte first
  EXPECT_EQ(bytes[23], 0x08);
  const std::optional<LockAnnouncement> back = decodeLockAnnouncement(bytes);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->rate.numerator, 60000);
  EXPECT_EQ(back->rate.denominator, 1001);
  EXPECT_EQ(back->epoch, a.epoch);
  EXPECT_EQ(back->newestField, 4242u);
  EXPECT_EQ(back->senderPid, 77u);

  auto wrong = bytes;
  wrong[0] = 'X';
  EXPECT_FALSE(decodeLockAnnouncement(wrong));
  wrong = bytes;
  wrong[5] = 2;  // a later version
  EXPECT_FALSE(decodeLockAnnouncement(wrong));
  EXPECT_FALSE(decodeLockAnnouncement(std::span(bytes.data(), 39)));
}

TEST(FieldLockLink, EachChannelHearsTheOthersAndTheEarliestEpochIsKept) {
  SystemClock clock;
  const TimePoint now = clock.now();
  const std::uint16_t pa = freePort(), pb = freePort(), pc = freePort(), ps = freePort();
  // a hears b and c; b and c hear a
  FieldLockLink a({loopback(pa), {loopback(pb), loopback(pc)}, LockTimeBase::Monotonic, 20ms}, kNtsc, clock);
  FieldLockLink b({loopback(pb), {loopback(pa)}, LockTimeBase::Monotonic, 20ms}, kNtsc, clock);
  FieldLockLink c({loopback(pc), {loopback(pa)}, LockTimeBase::Monotonic, 20ms}, kNtsc, clock);
  a.announce(now - 5s, 300);
  b.announce(now - 2s, 120);
  c.announce(now - 9s, 540);
  for (FieldLockLink* link : {&a, &b, &c}) link->start();

  ASSERT_TRUE(within3s([&] { return a.earliestEpochHeard() == now - 9s; }))
      << "a did not come to c's epoch (9 s ago, earlier than b's)";
  ASSERT_TRUE(within3s([&] { return b.earliestEpochHeard() == now - 5s; }));
  ASSERT_TRUE(within3s([&] { return c.earliestEpochHeard() == now - 5s; }));  // later than its own: kept anyway
  // A stranger — not one of a's peers — announcing a still earlier lock is not heard
  FieldLockLink stranger({loopback(ps), {loopback(pa)}, LockTimeBase::Monotonic, 20ms}, kNtsc, clock);
  stranger.announce(now - 60s, 3600);
  stranger.start();
  ASSERT_TRUE(within3s([&] { return a.counters().strangers > 2; }));
  // nor does a later epoch displace the earliest
  EXPECT_EQ(a.earliestEpochHeard(), now - 9s);
  for (FieldLockLink* link : {&a, &b, &c, &stranger}) link->stop();
  EXPECT_GT(b.counters().sent, 2u);
  EXPECT_GT(a.counters().received, 4u);
  EXPECT_EQ(a.counters().malformed, 0u);
}

TEST(FieldLockLink, AnotherRateAGarbageDatagramAndAnEpochNotOfThisClockAreNotHeard) {
  SystemClock clock;
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in from = parseUdpAddress("127.0.0.1:0", "test");
  ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&from), sizeof from), 0);
  socklen_t length = sizeof from;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&from), &length);
  FieldLockLink link({"127.0.0.1:0", {loopback(ntohs(from.sin_port))}, LockTimeBase::Monotonic, 20ms}, kNtsc, clock);
  link.start();
  const sockaddr_in to = parseUdpAddress(loopback(link.port()), "test");
  const auto send = [&](std::span<const std::uint8_t> bytes) {
    ::sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
  };
  LockAnnouncement fifty;
  fifty.rate = {50, 1};
  fifty.epoch = clock.now() - 1s;
  send(encodeLockAnnouncement(fifty));
  const std::uint8_t garbage[40] = {'F', 'C', 'L', 'X'};
  send(garbage);
  LockAnnouncement future;
  future.rate = kNtsc;
  future.epoch = clock.now() + 3600s;  // another machine's clock, say
  send(encodeLockAnnouncement(future));
  LockAnnouncement ancient = future;
  ancient.epoch = clock.now() - std::chrono::hours(24 * 365 * 11);  // older than any lock
  send(encodeLockAnnouncement(ancient));
  ASSERT_TRUE(within3s([&] { return link.counters().otherRate == 1 && link.counters().malformed == 3; }));
  EXPECT_FALSE(link.earliestEpochHeard());
  EXPECT_EQ(link.counters().received, 0u);
  ::close(fd);
  link.stop();
}

TEST(FieldLockLink, OnTheTaiClockAnEpochCrossesAsTheSameInstant) {
  LockAnnouncement tai;
  tai.rate = kNtsc;
  tai.timeBase = LockTimeBase::Tai;
  const auto bytes = encodeLockAnnouncement(tai);
  EXPECT_EQ(bytes[7], 1);
  EXPECT_EQ(decodeLockAnnouncement(bytes)->timeBase, LockTimeBase::Tai);
  auto unknown = bytes;
  unknown[7] = 2;
  EXPECT_FALSE(decodeLockAnnouncement(unknown));

  // Sent as an instant of CLOCK_TAI, heard as the same instant of CLOCK_MONOTONIC (one machine:
  // the two conversions differ by their reading noise only). A channel on CLOCK_MONOTONIC does
  // not follow it.
  SystemClock clock;
  const std::uint16_t senderPort = freePort();
  FieldLockLink hearsTai({"127.0.0.1:0", {loopback(senderPort)}, LockTimeBase::Tai, 20ms}, kNtsc, clock);
  FieldLockLink hearsMonotonic({"127.0.0.1:0", {loopback(senderPort)}, LockTimeBase::Monotonic, 20ms}, kNtsc, clock);
  // and a plain socket, to read what goes on the wire
  const int wire = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in wireAddress = parseUdpAddress("127.0.0.1:0", "test");
  ASSERT_EQ(::bind(wire, reinterpret_cast<const sockaddr*>(&wireAddress), sizeof wireAddress), 0);
  socklen_t length = sizeof wireAddress;
  ::getsockname(wire, reinterpret_cast<sockaddr*>(&wireAddress), &length);
  FieldLockLink sender(
      {loopback(senderPort),
       {loopback(hearsTai.port()), loopback(hearsMonotonic.port()), loopback(ntohs(wireAddress.sin_port))},
       LockTimeBase::Tai,
       20ms},
      kNtsc, clock);
  const TimePoint epoch = clock.now() - 3s;
  sender.announce(epoch, 180);
  for (FieldLockLink* link : {&sender, &hearsTai, &hearsMonotonic}) link->start();
  // On the wire the epoch is an instant of CLOCK_TAI
  std::uint8_t datagram[64];
  timeval timeout{3, 0};
  ::setsockopt(wire, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  ASSERT_EQ(::recv(wire, datagram, sizeof datagram, 0), 40);
  ::close(wire);
  // TAI − monotonic: the tightest of three readings of TAI between two of the monotonic clock (a
  // stall of the machine between two reads would shift a single one)
  Nanoseconds taiMinusMonotonic{0}, tightest = Nanoseconds::max();
  for (int attempt = 0; attempt < 3; ++attempt) {
    const TimePoint before = clock.now();
    timespec taiNow{};
    clock_gettime(CLOCK_TAI, &taiNow);
    const TimePoint after = clock.now();
    if (after - before >= tightest) continue;
    tightest = after - before;
    taiMinusMonotonic = Nanoseconds{static_cast<std::int64_t>(taiNow.tv_sec) * 1'000'000'000 + taiNow.tv_nsec} -
                        (before.time_since_epoch() + (after - before) / 2);
  }
  const std::optional<LockAnnouncement> sent = decodeLockAnnouncement(std::span(datagram, 40));
  ASSERT_TRUE(sent);
  EXPECT_NEAR(static_cast<double>((sent->epoch - (epoch + taiMinusMonotonic)).count()), 0.0, 1e6)
      << "the epoch is sent on CLOCK_TAI";
  ASSERT_TRUE(within3s([&] { return hearsTai.earliestEpochHeard().has_value(); }));
  EXPECT_NEAR(static_cast<double>((*hearsTai.earliestEpochHeard() - epoch).count()), 0.0,
              static_cast<double>(kSameLockTolerance.count()) / 10);
  ASSERT_TRUE(within3s([&] { return hearsMonotonic.counters().otherRate > 0; }));
  EXPECT_FALSE(hearsMonotonic.earliestEpochHeard());
  // The same lock announced again moves nothing, though each conversion reads the clocks anew
  std::this_thread::sleep_for(200ms);
  const TimePoint first = *hearsTai.earliestEpochHeard();
  std::this_thread::sleep_for(200ms);
  EXPECT_EQ(*hearsTai.earliestEpochHeard(), first);
  EXPECT_GT(hearsTai.counters().received, 5u);
  for (FieldLockLink* link : {&sender, &hearsTai, &hearsMonotonic}) link->stop();
}

TEST(FieldLockLink, BadAddressesFailNamingTheKey) {
  SystemClock clock;
  try {
    FieldLockLink link({"localhost:7300", {}, LockTimeBase::Monotonic, 100ms}, kNtsc, clock);
    FAIL() << "a name is not an IPv4 address";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("lock.listen"), std::string::npos) << e.what();
  }
  try {
    FieldLockLink link({"127.0.0.1:0", {"127.0.0.1:70000"}, LockTimeBase::Monotonic, 100ms}, kNtsc, clock);
    FAIL() << "port 70000";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("lock.peers"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fieldcast::io
