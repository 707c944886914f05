#pragma once
// Uncompressed video over RTP/UDP (RFC 4175, 8-bit YCbCr 4:2:2), the way SMPTE ST 2110-20
// gear and GStreamer/ffmpeg receivers take raw video. Each field is packetised on its own
// (interlaced: one RTP timestamp and one marker per field), and its packets are spread over most
// of the field period instead of leaving in one burst that would overrun a receiver's socket.

#include <io_bridge/FieldSink.h>

#include <fieldcast/Time.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace fieldcast::io {

struct RtpVideoSinkOptions {
  std::string address = "127.0.0.1";  ///< destination host (IPv4/IPv6 literal or name; multicast ok)
  int port = 5004;                    ///< destination UDP port (RTP; even by convention)
  int mtuBytes = 1400;                ///< largest IP packet
  int payloadType = 96;               ///< dynamic RTP payload type
  int multicastTtl = 16;
  /// Fraction of the field period the packets of one field are spread over; 0 sends each field
  /// as one burst (benchmarks).
  double pacingFraction = 0.9;
  /// Sending rounds per field: packets leave in this many evenly timed groups (sendmmsg each).
  int pacingRounds = 32;
  /// Where to write the SDP description a receiver opens (ffplay, VLC, GStreamer); empty: none.
  std::filesystem::path sdpPath;
  /// The time base pacing sleeps on; null means the system's monotonic clock.
  std::shared_ptr<Clock> clock;
};

/// Counters of an RtpVideoSink (read from the worker or after close()).
struct RtpFigures {
  std::uint64_t fields = 0;
  std::uint64_t packets = 0;
  std::uint64_t bytes = 0;         ///< UDP payload bytes sent
  std::uint64_t sendErrors = 0;    ///< packets the kernel refused (buffer full, no route, no listener)
  std::uint32_t nextSequence = 0;  ///< extended sequence number of the next packet
};

/// Sends every field as RFC 4175 packets. Not RT-safe (sockets, sleeps): runs on a SinkHub worker.
class RtpVideoSink final : public FieldSink {
 public:
  explicit RtpVideoSink(RtpVideoSinkOptions options);
  ~RtpVideoSink() override;

  std::string name() const override { return "rtp"; }
  /// Resolves the address, opens the socket, allocates packet storage for the largest field,
  /// writes the SDP file. Throws naming the address or file at fault.
  void open(const StreamFormat& format) override;
  SinkStatus consume(const Field& field) override;
  void close() override;

  /// The SDP session description of this stream (RFC 8866 with the RFC 4175 fmtp parameters).
  static std::string sdp(const StreamFormat& format, const RtpVideoSinkOptions& options);
  /// RTP timestamp of an instant: 90 kHz ticks of CLOCK_MONOTONIC plus a per-stream offset, mod 2³².
  static std::uint32_t rtpTimestamp(TimePoint t, std::uint32_t offset) noexcept;
  RtpFigures figures() const noexcept;

 private:
  struct State;
  RtpVideoSinkOptions mOptions;
  std::unique_ptr<State> mState;
};

}  // namespace fieldcast::io
