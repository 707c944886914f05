#pragma once
// Writes UDP datagrams to a classic libpcap capture file (not pcapng) that Wireshark and tshark
// open: the global header, then one Ethernet II / IPv4 / UDP frame per datagram between the given
// IPv4 endpoints. The IPv4 header checksum is computed; the UDP checksum is 0 ("none", allowed
// over IPv4). For diagnostics and interop tests (fieldcast-host --pcap, the CIGI tshark test).

#include <cstdint>
#include <fstream>
#include <mutex>
#include <span>
#include <string>
#include <vector>

namespace fieldcast::io {

/// One end of a UDP datagram: IPv4 address in host byte order (0x7F000001 is 127.0.0.1), port.
struct UdpEndpoint {
  std::uint32_t ipv4 = 0x7F000001;
  std::uint16_t port = 0;
};

class PcapWriter {
 public:
  /// Creates (truncates) the file and writes the global header. Throws std::runtime_error
  /// naming the file when it cannot be written.
  explicit PcapWriter(const std::string& path);

  /// Appends one datagram from `source` to `destination`, stamped `timeUs` microseconds after the
  /// Unix epoch. Buffered, so most calls make no system call: flush() or the destructor
  /// completes the file. Thread-safe: frames are written in call order, and a stamp earlier than
  /// the previous frame's is raised to it, so the file stays in time order. Throws
  /// std::runtime_error naming the file when a write fails.
  void writeUdp(UdpEndpoint source, UdpEndpoint destination, std::span<const std::uint8_t> payload,
                std::uint64_t timeUs);

  /// Writes out what is buffered. Throws std::runtime_error naming the file when that fails.
  void flush();

  /// Frames written so far. Thread-safe.
  int frames() const;

 private:
  std::string mPath;
  mutable std::mutex mMutex;  // guards everything below
  std::ofstream mOut;
  std::vector<std::uint8_t> mFrame;  // reused for each frame
  std::uint64_t mLastTimeUs = 0;
  std::uint16_t mIpId = 1;
  int mFrames = 0;
};

}  // namespace fieldcast::io
