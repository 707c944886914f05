// RFC 4175 sender: packetise a field into preallocated packets, then send them in evenly timed
// rounds over `pacingFraction` of the field period (sendmmsg per round). UDP errors are counted,
// never fatal: a receiver that is not listening yet must not end the stream.

#include <io_bridge/Rfc4175Packetizer.h>
#include <io_bridge/RtpVideoSink.h>

#include "PixelConvert.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace fieldcast::io {

struct RtpVideoSink::State {
  StreamFormat format;
  int fd = -1;
  std::shared_ptr<Clock> clock;
  std::unique_ptr<Rfc4175Packetizer> packetizer;
  RtpPacketBatch batch;
  std::vector<std::uint8_t> lines;  // the field converted to 4:2:2 when it is not UYVY already
  std::vector<mmsghdr> messages;
  std::vector<iovec> vectors;
  std::uint32_t timestampOffset = 0;
  Nanoseconds fieldPeriod{};
  RtpFigures figures;

  void sendRange(int first, int last) noexcept;
};

RtpVideoSink::RtpVideoSink(RtpVideoSinkOptions options) : mOptions(std::move(options)) {}
RtpVideoSink::~RtpVideoSink() { close(); }

std::uint32_t RtpVideoSink::rtpTimestamp(TimePoint t, std::uint32_t offset) noexcept {
  // 90 kHz = 9 ticks per 100 µs; ns·9/100000 stays in 64 bits for ~30 years of uptime.
  const auto ns = static_cast<std::uint64_t>(t.time_since_epoch().count());
  return static_cast<std::uint32_t>(ns / 100000 * 9 + (ns % 100000) * 9 / 100000) + offset;
}

std::string RtpVideoSink::sdp(const StreamFormat& format, const RtpVideoSinkOptions& options) {
  const bool v6 = options.address.find(':') != std::string::npos;
  const char* family = v6 ? "IP6" : "IP4";
  bool multicast = false;
  if (!v6) {
    in_addr a{};
    if (inet_pton(AF_INET, options.address.c_str(), &a) == 1) multicast = IN_MULTICAST(ntohl(a.s_addr));
  }
  const RationalRate frames = format.frameRate();
  std::ostringstream s;
  s << "v=0\r\n"
    << "o=- " << (static_cast<std::uint64_t>(MonotonicClock::now().time_since_epoch().count()) / 1000000) << " 1 IN "
    << family << ' ' << (v6 ? "::1" : "127.0.0.1") << "\r\n"
    << "s=Fieldcast raw video\r\n"
    << "c=IN " << family << ' ' << options.address;
  if (multicast) s << '/' << options.multicastTtl;  // (a string concatenation here set off GCC 12's -Wrestrict)
  s << "\r\n"
    << "t=0 0\r\n"
    << "m=video " << options.port << " RTP/AVP " << options.payloadType << "\r\n"
    << "a=rtpmap:" << options.payloadType << " raw/90000\r\n"
    << "a=fmtp:" << options.payloadType << " sampling=YCbCr-4:2:2; width=" << format.widthPx
    << "; height=" << format.heightPx << "; depth=8; colorimetry=" << (format.heightPx <= 576 ? "BT601-5" : "BT709-2")
    << (format.scan == ScanMode::Interlaced ? "; interlace" : "")
    << (format.scan == ScanMode::Interlaced && format.fieldOrder == FieldOrder::TopFirst ? "; top-field-first" : "")
    << "; exactframerate=" << frames.numerator << '/' << frames.denominator << "\r\n"
    << "a=framerate:" << frames.hz() << "\r\n"
    << "a=recvonly\r\n";
  return s.str();
}

void RtpVideoSink::open(const StreamFormat& format) {
  format.validate();
  auto st = std::make_unique<State>();
  st->format = format;
  st->clock = mOptions.clock ? mOptions.clock : std::make_shared<SystemClock>();
  st->fieldPeriod = format.fieldRate.period();
  const std::string where = mOptions.address + ":" + std::to_string(mOptions.port);

  addrinfo hints{};
  hints.ai_socktype = SOCK_DGRAM;
  hints.ai_protocol = IPPROTO_UDP;
  addrinfo* found = nullptr;
  const int rc = getaddrinfo(mOptions.address.c_str(), std::to_string(mOptions.port).c_str(), &hints, &found);
  if (rc != 0) throw std::runtime_error("sinks.rtp: cannot resolve " + where + ": " + gai_strerror(rc));
  st->fd = ::socket(found->ai_family, SOCK_DGRAM | SOCK_CLOEXEC, IPPROTO_UDP);
  if (st->fd < 0) {
    freeaddrinfo(found);
    throw std::runtime_error("sinks.rtp: socket: " + std::string(std::strerror(errno)));
  }
  const int sendBuffer = 4 << 20;
  setsockopt(st->fd, SOL_SOCKET, SO_SNDBUF, &sendBuffer, sizeof sendBuffer);
  if (found->ai_family == AF_INET) {
    const int ttl = mOptions.multicastTtl;
    setsockopt(st->fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
  }
  // connect() fixes the destination, so send errors (ICMP unreachable) come back to us
  const int connected = ::connect(st->fd, found->ai_addr, found->ai_addrlen);
  const int connectErrno = errno;
  // The IP header the MTU must also hold: IPv6's is 20 bytes longer than IPv4's
  const int headerBytes = found->ai_family == AF_INET6 ? kIpv6UdpHeaderBytes : kIpUdpHeaderBytes;
  freeaddrinfo(found);
  if (connected != 0) {
    ::close(st->fd);
    throw std::runtime_error("sinks.rtp: cannot send to " + where + ": " + std::strerror(connectErrno));
  }

  std::random_device random;  // RFC 3550 §5.1: random SSRC, initial sequence and timestamp
  st->packetizer = std::make_unique<Rfc4175Packetizer>(
      format.widthPx, mOptions.mtuBytes, static_cast<std::uint8_t>(mOptions.payloadType), random(), headerBytes);
  st->packetizer->setSequence(random());
  st->timestampOffset = random();
  const FieldParity largest = format.scan == ScanMode::Progressive ? FieldParity::Progressive : FieldParity::Top;
  const int maxRows = format.fieldRows(largest);
  const int maxPackets = st->packetizer->packetsFor(maxRows);
  st->batch.reserve(maxPackets, st->packetizer->maxPacketBytes());
  st->lines.assign(st->packetizer->lineBytes() * static_cast<std::size_t>(maxRows), 0);
  st->messages.assign(static_cast<std::size_t>(maxPackets), mmsghdr{});
  st->vectors.assign(static_cast<std::size_t>(maxPackets), iovec{});

  if (!mOptions.sdpPath.empty()) {
    std::ofstream out(mOptions.sdpPath, std::ios::binary | std::ios::trunc);
    out << sdp(format, mOptions);
    if (!out) {
      ::close(st->fd);
      throw std::runtime_error("sinks.rtp: cannot write the SDP file " + mOptions.sdpPath.string());
    }
  }
  mState = std::move(st);
}

void RtpVideoSink::State::sendRange(int first, int last) noexcept {
  for (int i = first; i < last; ++i) {
    auto& v = vectors[static_cast<std::size_t>(i)];
    v.iov_base = const_cast<std::uint8_t*>(batch.data(i));
    v.iov_len = batch.size(i);
    auto& m = messages[static_cast<std::size_t>(i)];
    m = mmsghdr{};
    m.msg_hdr.msg_iov = &v;
    m.msg_hdr.msg_iovlen = 1;
  }
  int i = first;
  while (i < last) {
    const int sent = ::sendmmsg(fd, messages.data() + i, static_cast<unsigned>(last - i), 0);
    if (sent < 0) {
      if (errno == EINTR) continue;
      ++figures.sendErrors;  // the packet at i is lost (or carried a pending ICMP error): skip it
      ++i;
      continue;
    }
    for (int j = i; j < i + sent; ++j) figures.bytes += batch.size(j);
    figures.packets += static_cast<std::uint64_t>(sent);
    i += sent;
  }
}

SinkStatus RtpVideoSink::consume(const Field& field) {
  State& st = *mState;
  const int rows = field.image.heightPx();
  const std::uint8_t* lines = field.image.bytes().data();
  std::size_t stride = field.image.strideBytes();
  if (field.image.format() != PixelFormat::Uyvy422) {
    stride = st.packetizer->lineBytes();
    for (int r = 0; r < rows; ++r) {
      rowToUyvy(field.image.row(r), field.image.format(), field.image.widthPx(),
                st.lines.data() + static_cast<std::size_t>(r) * stride);
    }
    lines = st.lines.data();
  }
  const RtpField f = field.parity == FieldParity::Bottom ? RtpField::Bottom : RtpField::TopOrProgressive;
  const int n =
      st.packetizer->packetize(lines, stride, rows, f, rtpTimestamp(field.displayTime, st.timestampOffset), st.batch);
  ++st.figures.fields;

  const double fraction = std::clamp(mOptions.pacingFraction, 0.0, 1.0);
  const int rounds = fraction > 0.0 ? std::clamp(mOptions.pacingRounds, 1, std::max(1, n)) : 1;
  const TimePoint start = st.clock->now();
  const auto span = Nanoseconds{static_cast<std::int64_t>(static_cast<double>(st.fieldPeriod.count()) * fraction)};
  for (int r = 0; r < rounds; ++r) {
    st.sendRange(n * r / rounds, n * (r + 1) / rounds);
    if (r + 1 < rounds) st.clock->sleepUntil(start + span * (r + 1) / rounds);
  }
  st.figures.nextSequence = st.packetizer->sequence();
  return SinkStatus::Ok;
}

void RtpVideoSink::close() {
  if (mState && mState->fd >= 0) {
    ::close(mState->fd);
    mState->fd = -1;
  }
}

RtpFigures RtpVideoSink::figures() const noexcept { return mState ? mState->figures : RtpFigures{}; }

}  // namespace fieldcast::io
