// Classic libpcap file format (https://wiki.wireshark.org/Development/LibpcapFileFormat):
// a 24-byte global header, then per packet a 16-byte record header and the frame. Header fields
// are in the writer's byte order (the magic number tells readers which); frame contents are in
// network byte order.
#include "PcapWriter.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace fieldcast::io::cigi::testdata {

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

void putBigEndian16(std::vector<std::uint8_t>& frame, std::size_t at, std::uint16_t v) {
  frame[at] = static_cast<std::uint8_t>(v >> 8);
  frame[at + 1] = static_cast<std::uint8_t>(v & 0xFF);
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
  if (!mOut) throw std::runtime_error(path + ": cannot write the capture header");
}

void PcapWriter::writeUdp(std::uint16_t sourcePort, std::uint16_t destinationPort,
                          std::span<const std::uint8_t> payload, std::uint64_t timeUs) {
  const std::size_t udpLength = kUdpBytes + payload.size();
  const std::size_t ipLength = kIpv4Bytes + udpLength;
  if (ipLength > 65535) throw std::runtime_error(mPath + ": datagram too large for IPv4");
  std::vector<std::uint8_t> frame(kEthernetBytes + ipLength, 0);

  // Ethernet II: locally administered MACs, EtherType IPv4.
  const std::uint8_t destinationMac[6] = {0x02, 0, 0, 0, 0, 0x02};
  const std::uint8_t sourceMac[6] = {0x02, 0, 0, 0, 0, 0x01};
  std::copy(destinationMac, destinationMac + 6, frame.begin());
  std::copy(sourceMac, sourceMac + 6, frame.begin() + 6);
  putBigEndian16(frame, 12, 0x0800);

  // IPv4: version 4, 5-word header, don't fragment, TTL 64, UDP, 127.0.0.1 → 127.0.0.1.
  std::uint8_t* ip = frame.data() + kEthernetBytes;
  ip[0] = 0x45;
  putBigEndian16(frame, kEthernetBytes + 2, static_cast<std::uint16_t>(ipLength));
  putBigEndian16(frame, kEthernetBytes + 4, mIpId++);
  putBigEndian16(frame, kEthernetBytes + 6, 0x4000);
  ip[8] = 64;
  ip[9] = 17;
  const std::uint8_t loopback[4] = {127, 0, 0, 1};
  std::copy(loopback, loopback + 4, ip + 12);
  std::copy(loopback, loopback + 4, ip + 16);
  putBigEndian16(frame, kEthernetBytes + 10, ipv4Checksum(ip));

  // UDP: ports, length, checksum 0.
  const std::size_t udp = kEthernetBytes + kIpv4Bytes;
  putBigEndian16(frame, udp, sourcePort);
  putBigEndian16(frame, udp + 2, destinationPort);
  putBigEndian16(frame, udp + 4, static_cast<std::uint16_t>(udpLength));
  std::copy(payload.begin(), payload.end(), frame.begin() + static_cast<std::ptrdiff_t>(udp + kUdpBytes));

  writeNative(mOut, static_cast<std::uint32_t>(timeUs / 1000000));
  writeNative(mOut, static_cast<std::uint32_t>(timeUs % 1000000));
  writeNative(mOut, static_cast<std::uint32_t>(frame.size()));
  writeNative(mOut, static_cast<std::uint32_t>(frame.size()));
  mOut.write(reinterpret_cast<const char*>(frame.data()), static_cast<std::streamsize>(frame.size()));
  mOut.flush();
  if (!mOut) throw std::runtime_error(mPath + ": cannot write a frame");
  ++mFrames;
}

}  // namespace fieldcast::io::cigi::testdata
