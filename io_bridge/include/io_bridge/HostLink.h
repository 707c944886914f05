#pragma once
// The IG's end of the CIGI link to a simulator host: one UDP socket and one thread. The thread
// receives the host's datagrams, decodes them (cigi::HostDatagramDecoder) and hands each
// accepted message to the HostHandler; once per field, when the field thread calls
// fieldStarted(), it asks the handler for that field's Start of Frame and responses and sends
// them. The field thread only writes an eventfd: it never waits on the network.
//
// Replies go to the address of the last accepted datagram, at its source port unless a reply
// port is configured. The socket listens on 127.0.0.1 unless configured otherwise.

#include <io_bridge/cigi/DatagramDecoder.h>
#include <io_bridge/cigi/MessageBuilder.h>

#include <fieldcast/SeqLock.h>
#include <fieldcast/Time.h>

#include <netinet/in.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace fieldcast::io {

/// Where the link listens and answers.
struct HostLinkConfig {
  std::string listenAddress = "127.0.0.1";  ///< an IPv4 address of this machine ("0.0.0.0": all)
  std::uint16_t port = 8004;                ///< the IG's port (0: any free port, for tests)
  std::uint16_t replyPort = 0;              ///< the host's port for IG→host messages; 0: the sender's port
  std::function<void()> onThreadStart;      ///< run first on the link's thread (its scheduling); may be empty
};

/// One accepted host→IG message.
struct HostMessage {
  std::span<const cigi::HostPacket> packets;  ///< IG Control first
  TimePoint arrival{};                        ///< IG clock when the datagram was read
  bool byteSwapped = false;                   ///< the host's byte order is not ours
};

/// One field, as the field thread announces it.
struct FieldAnnouncement {
  std::uint64_t fieldNumber = 0;
  TimePoint displayTime{};
};

/// What the link does with messages and fields. Both calls come from the link's thread, so a
/// handler needs no lock for the state only they touch.
class HostHandler {
 public:
  virtual ~HostHandler() = default;
  /// An accepted message from the host.
  virtual void onMessage(const HostMessage& message) = 0;
  /// A field started: write its Start of Frame (out.start) and the responses due (out.add) into
  /// `out` and return true to send them; false sends nothing.
  virtual bool onField(const FieldAnnouncement& field, cigi::IgMessageBuilder& out) = 0;
};

/// Figures of the link. Read from any thread.
struct HostLinkCounters {
  std::uint64_t datagramsReceived = 0;
  std::uint64_t datagramsAccepted = 0;
  std::uint64_t datagramsByteSwapped = 0;
  std::uint64_t datagramsRejected = 0;
  std::array<std::uint64_t, cigi::kRejectReasonCount> rejectedByReason{};
  std::uint64_t packetsSkipped = 0;  ///< unknown packets inside accepted datagrams
  std::uint64_t messagesSent = 0;    ///< IG→host datagrams (one per field once a host was heard)
  std::uint64_t fieldsWithoutHost = 0;
  std::uint64_t sendErrors = 0;
  std::uint64_t fieldsCoalesced = 0;  ///< fields announced but never served (a newer one was, the link was late)
};

class HostLink {
 public:
  /// Opens and binds the socket. Throws std::runtime_error naming the address on failure.
  HostLink(const HostLinkConfig& config, Clock& clock, HostHandler& handler);
  ~HostLink();
  HostLink(const HostLink&) = delete;
  HostLink& operator=(const HostLink&) = delete;

  /// The port the socket is bound to (the configured one, or the one the system chose for 0).
  std::uint16_t port() const noexcept { return mPort; }

  void start();
  /// Stops the thread. Idempotent.
  void stop();

  /// The field thread's call, once per field: wakes the link to send that field's Start of
  /// Frame. `renumbered`: the field clock moved onto another frame lock just before this field
  /// (its number does not follow the last one's; no field was lost). RT-safe (atomic stores and
  /// one non-blocking write to an eventfd).
  void fieldStarted(std::uint64_t fieldNumber, TimePoint displayTime, bool renumbered = false) noexcept;

  HostLinkCounters counters() const noexcept;

 private:
  void run() noexcept;
  void receiveAll();
  void sendField();

  HostLinkConfig mConfig;
  Clock& mClock;
  HostHandler& mHandler;
  int mSocket = -1;
  int mWake = -1;  // eventfd: fields announced and stop requests
  std::uint16_t mPort = 0;
  std::thread mThread;
  std::atomic<bool> mStop{false};

  // The newest announced field (written by the field thread, read by the link thread), whole:
  // a Start of Frame never pairs one field's number with the next one's time.
  SeqLock<FieldAnnouncement> mAnnounced;
  std::atomic<bool> mAnnouncementPending{false};

  bool mAnnouncedAny = false;  // field thread only
  std::atomic<std::uint64_t> mFirstAnnounced{0};
  std::atomic<std::uint64_t> mRenumberedAt{0};  // a renumbered field's number, until sendField sees it; 0: none

  // Link thread only.
  bool mServedAny = false;
  std::uint64_t mLastServed = 0;  // the newest field whose announcement was served
  cigi::HostDatagramDecoder mDecoder;
  std::vector<cigi::HostPacket> mPackets;
  std::vector<std::uint8_t> mReceiveBuffer;
  cigi::IgMessageBuilder mOut;
  bool mHaveHost = false;
  sockaddr_in mHostAddress{};
  HostLinkCounters mCounting;  // the link thread's own copy, published after each wake

  void publishCounters();
  mutable std::mutex mCountersMutex;
  HostLinkCounters mPublished;
};

}  // namespace fieldcast::io
