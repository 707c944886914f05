#pragma once
// Writes UDP datagrams to a classic libpcap capture file (not pcapng): the global header, then
// one Ethernet II / IPv4 / UDP frame per datagram between 127.0.0.1 ports. The IPv4 header
// checksum is computed; the UDP checksum is 0 ("none", allowed over IPv4).

#include <cstdint>
#include <fstream>
#include <span>
#include <string>

namespace fieldcast::io::cigi::testdata {

class PcapWriter {
 public:
  /// Creates (truncates) the file and writes the global header. Throws std::runtime_error
  /// naming the file when it cannot be written.
  explicit PcapWriter(const std::string& path);

  /// Appends one datagram from 127.0.0.1:`sourcePort` to 127.0.0.1:`destinationPort`, stamped
  /// `timeUs` microseconds after the epoch.
  void writeUdp(std::uint16_t sourcePort, std::uint16_t destinationPort, std::span<const std::uint8_t> payload,
                std::uint64_t timeUs);

  /// Frames written so far.
  int frames() const noexcept { return mFrames; }

 private:
  std::string mPath;
  std::ofstream mOut;
  std::uint16_t mIpId = 1;
  int mFrames = 0;
};

}  // namespace fieldcast::io::cigi::testdata
