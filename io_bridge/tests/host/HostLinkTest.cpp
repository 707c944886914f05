// HostLink over real loopback sockets: a test "host" socket sends CIGI datagrams to the link and
// reads back what the link sends for each announced field.
#include <io_bridge/HostLink.h>
#include <io_bridge/cigi/DatagramDecoder.h>
#include <io_bridge/cigi/MessageBuilder.h>

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

namespace fieldcast::io {
namespace {

using namespace std::chrono_literals;

// Records what the link hands over; answers each field with a Start of Frame naming it.
class RecordingHandler final : public HostHandler {
 public:
  void onMessage(const HostMessage& message) override {
    const std::lock_guard lock(mMutex);
    ++mMessages;
    mLastSwapped = message.byteSwapped;
    mLastPackets.assign(message.packets.begin(), message.packets.end());
    mChanged.notify_all();
  }
  bool onField(const FieldAnnouncement& field, cigi::IgMessageBuilder& out) override {
    const std::lock_guard lock(mMutex);
    ++mFields;
    mFieldNumbers.push_back(field.fieldNumber);
    cigi::StartOfFrame sof;
    sof.igFrameNumber = static_cast<std::uint32_t>(field.fieldNumber);
    out.start(sof);
    out.add(cigi::HatHotResponse{7, true, cigi::HatHotResponseType::HeightOfTerrain, 0, 123.5});
    mChanged.notify_all();
    return true;
  }
  bool waitMessages(int n) {
    std::unique_lock lock(mMutex);
    return mChanged.wait_for(lock, 5s, [&] { return mMessages >= n; });
  }
  bool waitFields(int n) {
    std::unique_lock lock(mMutex);
    return mChanged.wait_for(lock, 5s, [&] { return mFields >= n; });
  }
  int messages() {
    const std::lock_guard lock(mMutex);
    return mMessages;
  }
  std::vector<cigi::HostPacket> lastPackets() {
    const std::lock_guard lock(mMutex);
    return mLastPackets;
  }
  bool lastSwapped() {
    const std::lock_guard lock(mMutex);
    return mLastSwapped;
  }
  std::vector<std::uint64_t> fieldNumbers() {
    const std::lock_guard lock(mMutex);
    return mFieldNumbers;
  }

 private:
  std::mutex mMutex;
  std::condition_variable mChanged;
  int mMessages = 0, mFields = 0;
  bool mLastSwapped = false;
  std::vector<cigi::HostPacket> mLastPackets;
  std::vector<std::uint64_t> mFieldNumbers;
};

// A UDP socket on 127.0.0.1 playing the host.
class TestHost {
 public:
  explicit TestHost(std::uint16_t port = 0) {
    mSocket = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::bind(mSocket, reinterpret_cast<const sockaddr*>(&a), sizeof a), 0);
  }
  ~TestHost() { ::close(mSocket); }
  std::uint16_t port() const {
    sockaddr_in a{};
    socklen_t length = sizeof a;
    ::getsockname(mSocket, reinterpret_cast<sockaddr*>(&a), &length);
    return ntohs(a.sin_port);
  }
  void sendTo(std::uint16_t port, std::span<const std::uint8_t> bytes) const {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(::sendto(mSocket, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&a), sizeof a),
              static_cast<ssize_t>(bytes.size()));
  }
  // The next datagram within `timeout`, or nothing.
  std::optional<std::vector<std::uint8_t>> receive(std::chrono::milliseconds timeout = 2000ms) const {
    pollfd fd{mSocket, POLLIN, 0};
    if (::poll(&fd, 1, static_cast<int>(timeout.count())) <= 0) return std::nullopt;
    std::vector<std::uint8_t> buffer(65536);
    const ssize_t n = ::recv(mSocket, buffer.data(), buffer.size(), 0);
    if (n < 0) return std::nullopt;
    buffer.resize(static_cast<std::size_t>(n));
    return buffer;
  }

 private:
  int mSocket = -1;
};

std::vector<std::uint8_t> hostMessage(cigi::ByteOrder order, std::uint32_t frame) {
  cigi::HostMessageBuilder builder(order);
  cigi::IgControl control;
  control.hostFrameNumber = frame;
  builder.start(control);
  cigi::EntityControl ownship;
  ownship.latitudeDegOrXM = 47.25;
  ownship.yawDeg = 90.0f;
  builder.add(ownship);
  const auto bytes = builder.bytes();
  return {bytes.begin(), bytes.end()};
}

HostLinkConfig anyPort() {
  HostLinkConfig config;
  config.port = 0;
  return config;
}

TEST(HostLink, HandsOverDecodedMessagesInEitherByteOrder) {
  SystemClock clock;
  RecordingHandler handler;
  HostLink link(anyPort(), clock, handler);
  link.start();
  TestHost host;
  host.sendTo(link.port(), hostMessage(cigi::nativeByteOrder(), 41));
  ASSERT_TRUE(handler.waitMessages(1));
  auto packets = handler.lastPackets();
  ASSERT_EQ(packets.size(), 2u);
  EXPECT_EQ(std::get<cigi::IgControl>(packets[0]).hostFrameNumber, 41u);
  EXPECT_EQ(std::get<cigi::EntityControl>(packets[1]).latitudeDegOrXM, 47.25);
  EXPECT_FALSE(handler.lastSwapped());

  host.sendTo(link.port(), hostMessage(cigi::swappedByteOrder(), 42));
  ASSERT_TRUE(handler.waitMessages(2));
  packets = handler.lastPackets();
  EXPECT_EQ(std::get<cigi::IgControl>(packets[0]).hostFrameNumber, 42u);
  EXPECT_EQ(std::get<cigi::EntityControl>(packets[1]).yawDeg, 90.0f);
  EXPECT_TRUE(handler.lastSwapped());
  link.stop();
  EXPECT_EQ(link.counters().datagramsAccepted, 2u);
  EXPECT_EQ(link.counters().datagramsByteSwapped, 1u);
}

TEST(HostLink, RejectedDatagramsAreCountedAndNeverHandedOver) {
  SystemClock clock;
  RecordingHandler handler;
  HostLink link(anyPort(), clock, handler);
  link.start();
  TestHost host;
  std::vector<std::uint8_t> noControl = hostMessage(cigi::nativeByteOrder(), 1);
  noControl.erase(noControl.begin(), noControl.begin() + cigi::IgControl::kSize);  // starts with Entity Control
  std::vector<std::uint8_t> cut = hostMessage(cigi::nativeByteOrder(), 1);
  cut.resize(cut.size() - 5);  // the entity packet runs past the end
  const std::vector<std::uint8_t> one{1};
  host.sendTo(link.port(), noControl);
  host.sendTo(link.port(), cut);
  host.sendTo(link.port(), one);
  host.sendTo(link.port(), hostMessage(cigi::nativeByteOrder(), 2));  // a good one last
  ASSERT_TRUE(handler.waitMessages(1));
  link.stop();
  EXPECT_EQ(handler.messages(), 1);
  const HostLinkCounters c = link.counters();
  EXPECT_EQ(c.datagramsReceived, 4u);
  EXPECT_EQ(c.datagramsRejected, 3u);
  EXPECT_EQ(c.rejectedByReason[static_cast<std::size_t>(cigi::RejectReason::NoLeadingControl)], 1u);
  EXPECT_EQ(c.rejectedByReason[static_cast<std::size_t>(cigi::RejectReason::PacketPastEnd)], 1u);
  EXPECT_EQ(c.rejectedByReason[static_cast<std::size_t>(cigi::RejectReason::TooShort)], 1u);
}

TEST(HostLink, EachFieldSendsTheHandlersMessageToTheHostOnceOneWasHeard) {
  SystemClock clock;
  RecordingHandler handler;
  HostLink link(anyPort(), clock, handler);
  link.start();
  TestHost host;
  // No host yet: the field is served but nothing can be sent.
  link.fieldStarted(1, clock.now());
  ASSERT_TRUE(handler.waitFields(1));
  EXPECT_FALSE(host.receive(200ms).has_value());

  host.sendTo(link.port(), hostMessage(cigi::nativeByteOrder(), 5));
  ASSERT_TRUE(handler.waitMessages(1));
  link.fieldStarted(2, clock.now());
  const auto reply = host.receive();
  ASSERT_TRUE(reply.has_value());
  cigi::IgDatagramDecoder decoder;
  std::vector<cigi::IgPacket> packets;
  ASSERT_TRUE(decoder.decode(*reply, packets));
  ASSERT_EQ(packets.size(), 2u);
  EXPECT_EQ(std::get<cigi::StartOfFrame>(packets[0]).igFrameNumber, 2u);
  EXPECT_EQ(std::get<cigi::HatHotResponse>(packets[1]).heightM, 123.5);
  link.stop();
  EXPECT_EQ(link.counters().fieldsWithoutHost, 1u);
  EXPECT_EQ(link.counters().messagesSent, 1u);
}

TEST(HostLink, AConfiguredReplyPortWinsOverTheSendersPort) {
  SystemClock clock;
  RecordingHandler handler;
  TestHost listener;  // the host's receiving socket, on a port of its own
  TestHost sender;
  HostLinkConfig config = anyPort();
  config.replyPort = listener.port();
  HostLink link(config, clock, handler);
  link.start();
  sender.sendTo(link.port(), hostMessage(cigi::nativeByteOrder(), 9));
  ASSERT_TRUE(handler.waitMessages(1));
  link.fieldStarted(3, clock.now());
  EXPECT_TRUE(listener.receive().has_value());
  EXPECT_FALSE(sender.receive(100ms).has_value());  // not to the sender's own port
  link.stop();
}

// 20,000 garbage datagrams while fields are announced: the link keeps serving fields (each
// announcement is served, or coalesced with the next when the link was busy) and counts the
// garbage; a good message after the flood still gets through.
TEST(HostLink, AGarbageFloodIsCountedAndFieldsAreStillServed) {
  SystemClock clock;
  RecordingHandler handler;
  HostLink link(anyPort(), clock, handler);
  link.start();
  TestHost host;
  host.sendTo(link.port(), hostMessage(cigi::nativeByteOrder(), 1));
  ASSERT_TRUE(handler.waitMessages(1));
  std::vector<std::uint8_t> garbage(64);
  int fieldsAnnounced = 0;
  for (int k = 0; k < 20000; ++k) {
    for (std::size_t b = 0; b < garbage.size(); ++b) garbage[b] = static_cast<std::uint8_t>(k * 31 + b * 7);
    host.sendTo(link.port(), garbage);
    if (k % 400 == 0) link.fieldStarted(static_cast<std::uint64_t>(++fieldsAnnounced), clock.now());
  }
  // Let the link drain the flood first: a datagram sent into a full socket buffer is dropped by
  // the kernel, and the good one must not be (on a busy machine the link drains slowly). Drained:
  // no datagram taken over three polls in a row (a stall of the whole machine during one poll
  // stops the link too, and would pass for a drained buffer).
  for (int quiet = 0; quiet < 3;) {
    const std::uint64_t before = link.counters().datagramsReceived;
    std::this_thread::sleep_for(100ms);
    quiet = link.counters().datagramsReceived == before ? quiet + 1 : 0;
  }
  host.sendTo(link.port(), hostMessage(cigi::nativeByteOrder(), 2));
  ASSERT_TRUE(handler.waitMessages(2));
  link.fieldStarted(static_cast<std::uint64_t>(++fieldsAnnounced), clock.now());
  int sofs = 0;
  while (host.receive(300ms)) ++sofs;
  link.stop();
  const HostLinkCounters c = link.counters();
  EXPECT_EQ(c.datagramsAccepted, 2u);
  EXPECT_GT(c.datagramsRejected, 0u);  // the rest may have been dropped by the socket's buffer
  EXPECT_EQ(c.datagramsReceived, c.datagramsAccepted + c.datagramsRejected);
  EXPECT_EQ(static_cast<std::uint64_t>(sofs) + c.fieldsCoalesced, static_cast<std::uint64_t>(fieldsAnnounced));
}

// Announcements faster than the link can serve them (no sleep between): every field is served
// once or counted as coalesced, in order — never served twice (an announcement raised while the
// link was reading the previous one), never lost uncounted. The first announced is not field 0.
// A move onto another frame lock renumbers the fields: the jump is not fields the link lost.
TEST(HostLink, ARenumberedFieldIsNotCountedAsCoalescedFields) {
  SystemClock clock;
  RecordingHandler handler;
  HostLink link(anyPort(), clock, handler);
  link.start();
  const auto announceAndWait = [&](std::uint64_t n, bool renumbered) {
    link.fieldStarted(n, clock.now(), renumbered);
    for (int i = 0; i < 200 && (handler.fieldNumbers().empty() || handler.fieldNumbers().back() != n); ++i)
      std::this_thread::sleep_for(5ms);
  };
  announceAndWait(10, false);
  announceAndWait(11, false);
  announceAndWait(5011, true);
  announceAndWait(5012, false);
  announceAndWait(5014, false);  // 5013 lost: counted
  link.stop();
  EXPECT_EQ(handler.fieldNumbers().size(), 5u);
  EXPECT_EQ(link.counters().fieldsCoalesced, 1u);
}

TEST(HostLink, FieldsAnnouncedFasterThanServedAreServedOnceOrCountedCoalesced) {
  SystemClock clock;
  RecordingHandler handler;
  HostLink link(anyPort(), clock, handler);
  link.start();
  constexpr std::uint64_t kFirst = 500, kFields = 50000;
  for (std::uint64_t n = kFirst; n < kFirst + kFields; ++n) link.fieldStarted(n, clock.now());
  for (int i = 0; i < 100 && (handler.fieldNumbers().empty() || handler.fieldNumbers().back() != kFirst + kFields - 1);
       ++i) {
    std::this_thread::sleep_for(20ms);
  }
  link.stop();
  const std::vector<std::uint64_t> served = handler.fieldNumbers();
  ASSERT_FALSE(served.empty());
  EXPECT_EQ(served.back(), kFirst + kFields - 1) << "the newest field is always served";
  for (std::size_t k = 1; k < served.size(); ++k) {
    ASSERT_GT(served[k], served[k - 1]) << "field " << served[k] << " served after " << served[k - 1];
  }
  EXPECT_EQ(served.size() + link.counters().fieldsCoalesced, kFields);
}

TEST(HostLink, ABadListenAddressIsRefusedByName) {
  SystemClock clock;
  RecordingHandler handler;
  HostLinkConfig config = anyPort();
  config.listenAddress = "localhost:8004";
  try {
    HostLink link(config, clock, handler);
    FAIL() << "accepted a bad address";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'localhost:8004' is not an IPv4 address"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fieldcast::io
