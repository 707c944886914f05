#include <io_bridge/RtpVideoSink.h>

#include "Rfc4175Reader.h"
#include "TestFields.h"

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace fieldcast::io {
namespace {

using testing::makeField;
using testing::testFormat;

// A loopback UDP receiver on an ephemeral port.
struct Receiver {
  int fd = -1;
  int port = 0;
  Receiver() {
    fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    const int big = 8 << 20;
    setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &big, sizeof big);
    setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &big, sizeof big);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    port = ntohs(a.sin_port);
    timeval tv{1, 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  }
  ~Receiver() { ::close(fd); }
  std::vector<std::uint8_t> next() {
    std::vector<std::uint8_t> b(65536);
    const ssize_t n = recv(fd, b.data(), b.size(), 0);
    b.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
    return b;
  }
};

TEST(RtpVideoSink, SendsEveryFieldIntactOverLoopback) {
  for (ScanMode scan : {ScanMode::Interlaced, ScanMode::Progressive}) {
    SCOPED_TRACE(scan == ScanMode::Interlaced ? "interlaced" : "progressive");
    const StreamFormat f = testFormat(176, 40, scan);
    Receiver rx;
    RtpVideoSinkOptions o;
    o.port = rx.port;
    o.mtuBytes = 1000;
    o.clock = std::make_shared<VirtualClock>();  // pacing in virtual time: no sleeping in the test
    RtpVideoSink sink(o);
    sink.open(f);
    std::uint32_t previousSequence = 0;
    std::uint32_t previousTimestamp = 0;
    for (std::uint64_t k = 0; k < 4; ++k) {
      const Field field = makeField(f, k);
      ASSERT_EQ(sink.consume(field), SinkStatus::Ok);
      std::vector<std::uint8_t> image(static_cast<std::size_t>(f.widthPx) * 2 *
                                      static_cast<std::size_t>(field.image.heightPx()));
      bool marker = false;
      std::uint32_t timestamp = 0;
      while (!marker) {
        const auto packet = rx.next();
        ASSERT_FALSE(packet.empty()) << "timed out waiting for field " << k;
        testing::ParsedPacket p;
        ASSERT_EQ(testing::parsePacket(packet.data(), packet.size(), static_cast<std::size_t>(f.widthPx) * 2,
                                       field.image.heightPx(), image, p),
                  "");
        if (k > 0 || timestamp != 0) {
          EXPECT_EQ(p.extendedSequence, previousSequence + 1);
        }
        previousSequence = p.extendedSequence;
        timestamp = p.timestamp;
        EXPECT_EQ(p.segments[0].field, field.parity == FieldParity::Bottom);
        marker = p.marker;
      }
      EXPECT_TRUE(std::equal(image.begin(), image.end(), field.image.bytes().begin())) << "field " << k;
      if (k > 0) {  // 1501.5 ticks a field: 1501 and 1502 alternate
        EXPECT_TRUE(timestamp - previousTimestamp == 1501u || timestamp - previousTimestamp == 1502u);
      }
      previousTimestamp = timestamp;
    }
    sink.close();
    EXPECT_EQ(sink.figures().fields, 4u);
    EXPECT_EQ(sink.figures().sendErrors, 0u);
  }
}

TEST(RtpVideoSink, PacingSpreadsAFieldOverMostOfItsPeriod) {
  const StreamFormat f = testFormat(720, 486);
  auto clock = std::make_shared<VirtualClock>(TimePoint{std::chrono::seconds(100)});
  Receiver rx;
  RtpVideoSinkOptions o;
  o.port = rx.port;
  o.clock = clock;
  o.pacingFraction = 0.9;
  o.pacingRounds = 10;
  RtpVideoSink sink(o);
  sink.open(f);
  sink.consume(makeField(f, 0, clock->now()));
  // Ten rounds: the last starts 9/10 of the way through 0.9 T
  const auto expected = f.fieldRate.period() * 9 / 10 * 9 / 10;
  EXPECT_NEAR(static_cast<double>((clock->now() - TimePoint{std::chrono::seconds(100)}).count()),
              static_cast<double>(expected.count()), 2.0);
}

TEST(RtpVideoSink, SdpDescribesTheStream) {
  StreamFormat f = testFormat(720, 486);
  RtpVideoSinkOptions o;
  o.address = "239.1.2.3";
  o.port = 5006;
  const std::string sdp = RtpVideoSink::sdp(f, o);
  EXPECT_NE(sdp.find("m=video 5006 RTP/AVP 96\r\n"), std::string::npos) << sdp;
  EXPECT_NE(sdp.find("c=IN IP4 239.1.2.3/16\r\n"), std::string::npos) << sdp;
  EXPECT_NE(sdp.find("a=rtpmap:96 raw/90000\r\n"), std::string::npos);
  EXPECT_NE(sdp.find("a=fmtp:96 sampling=YCbCr-4:2:2; width=720; height=486; depth=8; colorimetry=BT601-5; "
                     "interlace; exactframerate=30000/1001\r\n"),
            std::string::npos)
      << sdp;
  f = testFormat(1920, 1080, ScanMode::Progressive);
  EXPECT_NE(RtpVideoSink::sdp(f, {}).find("colorimetry=BT709-2; exactframerate=60000/1001"), std::string::npos);
}

TEST(RtpVideoSink, NoListenerIsNotAnError) {
  const StreamFormat f = testFormat(64, 16);
  int port;
  {
    Receiver gone;  // a port that was just free
    port = gone.port;
  }
  RtpVideoSinkOptions o;
  o.port = port;
  o.clock = std::make_shared<VirtualClock>();
  RtpVideoSink sink(o);
  sink.open(f);
  for (std::uint64_t k = 0; k < 5; ++k) EXPECT_EQ(sink.consume(makeField(f, k)), SinkStatus::Ok);
  sink.close();
  EXPECT_EQ(sink.figures().fields, 5u);
}

TEST(RtpVideoSink, BadAddressIsAClearError) {
  RtpVideoSinkOptions o;
  o.address = "no.such.host.invalid";
  RtpVideoSink sink(o);
  try {
    sink.open(testFormat(64, 16));
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no.such.host.invalid:5004"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fieldcast::io
