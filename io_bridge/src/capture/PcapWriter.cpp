// Classic libpcap file format (https://wiki.wireshark.org/Development/LibpcapFileFormat):
// a 24-byte global header, then per packet a 16-byte record header and the frame. Header fields
// are in the writer's byte order (the magic number tells readers which); frame contents are in
// network byte order.
#include <io_bridge/PcapWriter.h>

#include <algorithm>
#include <stdexcept>

namespace fieldcast::io {

namespace {

constexpr std::uint32_t kPcapMagic = 0xA1B2C3D4;  // microsecond timestamps
constexpr std::uint32_t kLinkTypeEthernet = 1;
constexpr std::uint32_t kSnapLength = 65535;
constexpr std::size_t kEthernetBytes = 14;
constexpr std::size_t kIpv4Bytes = 20;
constexpr std::size_t kUdpBytes = 8;

template <class T>
void writeNative(std::ofstream& out, T value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(value));
}

void putBigEndian16(std::uint8_t* at, std::uint16_t v) {
  at[0] = static_cast<std::uint8_t>(v >> 8);
  at[1] = static_cast<std::uint8_t>(v & 0xFF);
}

void putBigEndian32(std::uint8_t* at, std::uint32_t v) {
  putBigEndian16(at, static_cast<std::uint16_t>(v >> 16));
  putBigEndian16(at + 2, static_cast<std::uint16_t>(v & 0xFFFF));
}

/// RFC 791 header checksum: one's complement of the one's-complement sum of 16-bit words.
std::uint16_t ipv4Checksum(const std::uint8_t* header) {
  std::uint32_t sum = 0;
  for (std::size_t i = 0; i < kIpv4Bytes; i += 2) sum += (std::uint32_t{header[i]} << 8) | header[i + 1];
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  return static_cast<std::uint16_t>(~sum & 0xFFFF);
}

}  // namespace

PcapWriter::PcapWriter(const std::string& path) : mPath(path), mOut(path, std::ios::binary | std::ios::trunc) {
  if (!mOut) throw std::runtime_error(path + ": cannot create the capture file");
  writeNative(mOut, kPcapMagic);
  writeNative(mOut, std::uint16_t{2});  // version 2.4
  writeNative(mOut, std::uint16_t{4});
  writeNative(mOut, std::int32_t{0});   // GMT offset
  writeNative(mOut, std::uint32_t{0});  // timestamp accuracy
  writeNative(mOut, kSnapLength);
  writeNative(mOut, kLinkTypeEthernet);
  mOut.flush();
  if (!mOut) throw std::runtime_error(path + ": cannot write the capture header");
}

int PcapWriter::frames() const {
  const std::lock_guard lock(mMutex);
  return mFrames;
}

void PcapWriter::writeUdp(UdpEndpoint source, UdpEndpoint destination, std::span<const std::uint8_t> payload,
                          std::uint64_t timeUs) {
  const std::size_t udpLength = kUdpBytes + payload.size();
  const std::size_t ipLength = kIpv4Bytes + udpLength;
  if (ipLength > 65535) throw std::runtime_error(mPath + ": datagram too large for IPv4");

  const std::lock_guard lock(mMutex);
  mFrame.assign(kEthernetBytes + ipLength, 0);
  std::uint8_t* frame = mFrame.data();

  // Ethernet II: locally administered MACs, EtherType IPv4.
  const std::uint8_t destinationMac[6] = {0x02, 0, 0, 0, 0, 0x02};
  const std::uint8_t sourceMac[6] = {0x02, 0, 0, 0, 0, 0x01};
  std::copy(destinationMac, destinationMac + 6, frame);
  std::copy(sourceMac, sourceMac + 6, frame + 6);
  putBigEndian16(frame + 12, 0x0800);

  // IPv4: version 4, 5-word header, don't fragment, TTL 64, UDP.
  std::uint8_t* ip = frame + kEthernetBytes;
  ip[0] = 0x45;
  putBigEndian16(ip + 2, static_cast<std::uint16_t>(ipLength));
  putBigEndian16(ip + 4, mIpId++);
  putBigEndian16(ip + 6, 0x4000);
  ip[8] = 64;
  ip[9] = 17;
  putBigEndian32(ip + 12, source.ipv4);
  putBigEndian32(ip + 16, destination.ipv4);
  putBigEndian16(ip + 10, ipv4Checksum(ip));

  // UDP: ports, length, checksum 0.
  std::uint8_t* udp = ip + kIpv4Bytes;
  putBigEndian16(udp, source.port);
  putBigEndian16(udp + 2, destination.port);
  putBigEndian16(udp + 4, static_cast<std::uint16_t>(udpLength));
  std::copy(payload.begin(), payload.end(), udp + kUdpBytes);

  mLastTimeUs = std::max(mLastTimeUs, timeUs);
  writeNative(mOut, static_cast<std::uint32_t>(mLastTimeUs / 1000000));
  writeNative(mOut, static_cast<std::uint32_t>(mLastTimeUs % 1000000));
  writeNative(mOut, static_cast<std::uint32_t>(mFrame.size()));
  writeNative(mOut, static_cast<std::uint32_t>(mFrame.size()));
  mOut.write(reinterpret_cast<const char*>(frame), static_cast<std::streamsize>(mFrame.size()));
  // Buffered: a flush per datagram would put a write(2), which can stall for milliseconds, in
  // the caller's send loop.
  if (!mOut) throw std::runtime_error(mPath + ": cannot write a frame");
  ++mFrames;
}

void PcapWriter::flush() {
  const std::lock_guard lock(mMutex);
  mOut.flush();
  if (!mOut) throw std::runtime_error(mPath + ": cannot write the capture");
}

}  // namespace fieldcast::io
