#include "ScriptedHost.h"

#include "LosReference.h"

#include <io_bridge/cigi/DatagramDecoder.h>
#include <io_bridge/cigi/MessageBuilder.h>

#include <fieldcast/Pose.h>
#include <ig_core/LineOfSight.h>

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

namespace fieldcast::tools {
namespace {

namespace cigi = io::cigi;
using Steady = std::chrono::steady_clock;

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  const auto n = static_cast<double>(values.size());
  const auto k = static_cast<std::size_t>(std::min(n - 1.0, std::floor(p * n)));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

class Socket {
 public:
  explicit Socket(std::uint16_t port) {
    mFd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (mFd < 0) throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::bind(mFd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
      const std::string why = std::strerror(errno);
      ::close(mFd);
      throw std::runtime_error("cannot bind 127.0.0.1:" + std::to_string(port) + ": " + why);
    }
  }
  ~Socket() { ::close(mFd); }
  Socket(const Socket&) = delete;
  Socket& operator=(const Socket&) = delete;
  int fd() const noexcept { return mFd; }
  /// The bound address and port (the port the system chose when asked for 0).
  io::UdpEndpoint local() const {
    sockaddr_in a{};
    socklen_t length = sizeof a;
    ::getsockname(mFd, reinterpret_cast<sockaddr*>(&a), &length);
    return {ntohl(a.sin_addr.s_addr), ntohs(a.sin_port)};
  }

 private:
  int mFd = -1;
};

io::UdpEndpoint endpointOf(const sockaddr_in& a) { return {ntohl(a.sin_addr.s_addr), ntohs(a.sin_port)}; }

std::uint64_t wallClockUs() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
}

// The recorders as both threads use them: a capture that fails stops capturing and keeps its error
// for the end of the run (the threads do not throw).
class Recording {
 public:
  Recording(const ScriptedHostRecorders& recorders, io::UdpEndpoint host, io::UdpEndpoint ig)
      : mRecorders(recorders), mHost(host), mIg(ig) {
    if (mRecorders.sentLog != nullptr)
      *mRecorders.sentLog << "host_frame\tlat_deg\tlon_deg\talt_m\tyaw_deg\tpitch_deg\troll_deg\n";
  }

  // Recorded as it is handed to the socket, before any answer to it can arrive: the capture keeps
  // cause before effect.
  void sending(std::span<const std::uint8_t> datagram, io::UdpEndpoint to) { capture(mHost, to, datagram); }
  void received(const sockaddr_in& from, std::span<const std::uint8_t> datagram) {
    capture(endpointOf(from), mHost, datagram);
  }
  void sentOwnship(std::uint32_t hostFrame, const io::cigi::EntityControl& e) {
    if (mRecorders.sentLog == nullptr) return;
    char line[256];
    std::snprintf(line, sizeof line, "%u\t%.17g\t%.17g\t%.17g\t%.9g\t%.9g\t%.9g\n", hostFrame, e.latitudeDegOrXM,
                  e.longitudeDegOrYM, e.altitudeMOrZM, static_cast<double>(e.yawDeg), static_cast<double>(e.pitchDeg),
                  static_cast<double>(e.rollDeg));
    *mRecorders.sentLog << line;
  }
  /// Completes the recordings; throws the first recording error, if any.
  void check() {
    if (mRecorders.capture != nullptr && !mFailed.load()) mRecorders.capture->flush();
    if (mRecorders.sentLog != nullptr) mRecorders.sentLog->flush();
    if (mRecorders.sentLog != nullptr && !*mRecorders.sentLog)
      throw std::runtime_error("--sent-log: cannot write the file");
    const std::lock_guard lock(mMutex);
    if (!mError.empty()) throw std::runtime_error(mError);
  }

 private:
  void capture(io::UdpEndpoint from, io::UdpEndpoint to, std::span<const std::uint8_t> datagram) {
    if (mRecorders.capture == nullptr || mFailed.load()) return;
    try {
      mRecorders.capture->writeUdp(from, to, datagram, wallClockUs());
    } catch (const std::exception& e) {
      const std::lock_guard lock(mMutex);
      mFailed = true;
      mError = e.what();
    }
  }

  ScriptedHostRecorders mRecorders;
  io::UdpEndpoint mHost, mIg;
  std::atomic<bool> mFailed{false};
  std::mutex mMutex;  // guards mError
  std::string mError;
};

// A request in flight: where it asked and when it left.
struct PendingHeight {
  glm::dvec3 pointM;
  Steady::time_point sent;
};
struct PendingLos {
  glm::dvec3 fromM, toM;
  Steady::time_point sent;
};
// The IG's answer to a LOS request, with the segment asked about.
struct LosAnswer {
  glm::dvec3 fromM, toM;
  bool hit = false;
  double rangeM = 0.0;
};

// Makes the level-0 tiles under the segment resident (the reference's full-resolution answer).
void loadLevelZero(core::TileCache& terrain, const glm::dvec3& fromM, const glm::dvec3& toM) {
  bool requested = false;
  for (const glm::ivec2& t : core::lineOfSightTiles(terrain.geometry(), fromM, toM)) {
    if (terrain.view().tile(0, t.x, t.y) != nullptr) continue;
    terrain.request(0, t.x, t.y);
    requested = true;
  }
  if (requested) terrain.waitIdle(std::chrono::seconds(5));
}

}  // namespace

ScriptedHostReport runScriptedHost(const ScriptedHostOptions& options, const motion::ScriptedTrajectory& flight,
                                   core::TileCache& terrain, const core::Georeference& georeference,
                                   const ScriptedHostRecorders& recorders) {
  sockaddr_in ig{};
  ig.sin_family = AF_INET;
  ig.sin_port = htons(options.igPort);
  if (inet_pton(AF_INET, options.igAddress.c_str(), &ig.sin_addr) != 1) {
    throw std::runtime_error("--ig: '" + options.igAddress + "' is not an IPv4 address");
  }
  Socket socket(options.localPort);
  Recording recording(recorders, socket.local(), endpointOf(ig));
  std::vector<sockaddr_in> others;  // the rig's other channels
  for (const std::uint16_t port : options.otherIgPorts) {
    others.push_back(ig);
    others.back().sin_port = htons(port);
  }
  std::atomic<std::uint64_t> otherSendErrors{0};
  const auto sendTo = [&](const sockaddr_in& to, std::span<const std::uint8_t> bytes) {
    recording.sending(bytes, endpointOf(to));
    return ::sendto(socket.fd(), bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
  };
  // To every channel; the result is the measured IG's (another channel not running yet is no error)
  const auto send = [&](std::span<const std::uint8_t> bytes) {
    const ssize_t result = sendTo(ig, bytes);
    for (const sockaddr_in& other : others) {
      if (sendTo(other, bytes) < 0) otherSendErrors.fetch_add(1, std::memory_order_relaxed);
    }
    return result;
  };

  std::mutex mutex;  // guards pending, the report's lists and counters shared with the reader
  std::map<std::uint16_t, PendingHeight> pending;
  std::map<std::uint16_t, PendingLos> pendingLos;
  std::vector<double> sofIntervals, latenciesMs, losLatenciesMs;
  // Start of Frame arrivals by IG frame number: the measured IG's, and each other channel's
  std::map<std::uint32_t, Steady::time_point> sofArrivals;
  std::vector<std::map<std::uint32_t, Steady::time_point>> otherSofArrivals(others.size());
  std::vector<std::pair<glm::dvec3, double>> answers;  // where a valid answer was asked, and its height
  std::vector<LosAnswer> losAnswers;
  ScriptedHostReport report;
  report.otherStartOfFrames.assign(others.size(), 0);
  std::atomic<bool> stop{false};
  std::atomic<bool> heard{false};  // a Start of Frame has arrived

  // A LOS answer (caller holds the mutex).
  const auto takeLos = [&](std::uint16_t losId, bool hit, double rangeM, Steady::time_point arrival) {
    const auto it = pendingLos.find(losId);
    if (it == pendingLos.end()) return;
    ++report.losAnswers;
    if (hit) ++report.losHits;
    losLatenciesMs.push_back(std::chrono::duration<double, std::milli>(arrival - it->second.sent).count());
    losAnswers.push_back({it->second.fromM, it->second.toM, hit, rangeM});
    pendingLos.erase(it);
  };

  // The reader: Start of Frames and answers, timed on arrival.
  std::thread reader([&] {
    cigi::IgDatagramDecoder decoder;
    std::vector<cigi::IgPacket> packets;
    std::vector<std::uint8_t> buffer(cigi::kMaxDatagramBytes);
    std::optional<Steady::time_point> lastSof;
    while (!stop.load()) {
      pollfd fd{socket.fd(), POLLIN, 0};
      if (::poll(&fd, 1, 50) <= 0) continue;
      sockaddr_in from{};
      socklen_t fromLength = sizeof from;
      const ssize_t n =
          ::recvfrom(socket.fd(), buffer.data(), buffer.size(), 0, reinterpret_cast<sockaddr*>(&from), &fromLength);
      if (n <= 0) continue;
      const Steady::time_point arrival = Steady::now();
      const std::span<const std::uint8_t> datagram(buffer.data(), static_cast<std::size_t>(n));
      recording.received(from, datagram);
      if (from.sin_port != ig.sin_port) {  // another channel of the rig: its Start of Frames counted
        const auto other = std::find_if(others.begin(), others.end(),
                                        [&](const sockaddr_in& o) { return o.sin_port == from.sin_port; });
        if (other == others.end() || !decoder.decode(datagram, packets)) continue;
        const std::lock_guard lock(mutex);
        const auto index = static_cast<std::size_t>(other - others.begin());
        for (const cigi::IgPacket& packet : packets) {
          if (const auto* sof = std::get_if<cigi::StartOfFrame>(&packet)) {
            ++report.otherStartOfFrames[index];
            otherSofArrivals[index][sof->igFrameNumber] = arrival;
          }
        }
        continue;
      }
      if (!decoder.decode(datagram, packets)) continue;
      const std::lock_guard lock(mutex);
      for (const cigi::IgPacket& packet : packets) {
        if (const auto* sof = std::get_if<cigi::StartOfFrame>(&packet)) {
          ++report.startOfFrames;
          heard = true;
          if (sof->igStatus != 0) ++report.ownshipHeldFrames;
          if (lastSof) sofIntervals.push_back(std::chrono::duration<double>(arrival - *lastSof).count());
          lastSof = arrival;
          sofArrivals[sof->igFrameNumber] = arrival;
        } else if (const auto* answer = std::get_if<cigi::HatHotResponse>(&packet)) {
          ++report.heightAnswers;
          const auto it = pending.find(answer->hatHotId);
          if (it == pending.end()) continue;
          latenciesMs.push_back(std::chrono::duration<double, std::milli>(arrival - it->second.sent).count());
          if (answer->valid) {
            ++report.heightAnswersValid;
            answers.emplace_back(it->second.pointM, answer->heightM);
          }
          pending.erase(it);
        } else if (const auto* los = std::get_if<cigi::LosResponse>(&packet)) {
          takeLos(los->losId, los->valid, los->rangeM, arrival);
        } else if (const auto* extended = std::get_if<cigi::LosExtendedResponse>(&packet)) {
          takeLos(extended->losId, extended->valid && extended->rangeValid, extended->rangeM, arrival);
        }
      }
      report.rejectedDatagrams = decoder.counters().rejectedTotal();
    }
  });

  const cigi::ByteOrder order = options.byteSwapped ? cigi::swappedByteOrder() : cigi::nativeByteOrder();
  cigi::HostMessageBuilder message(order);
  std::mt19937 random(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // A host waits for its IG: IG Control alone, ten times a second, until a Start of Frame comes back.
  if (options.waitForIgS > 0) {
    const Steady::time_point giveUp =
        Steady::now() + std::chrono::duration_cast<Steady::duration>(std::chrono::duration<double>(options.waitForIgS));
    while (!heard.load()) {
      if (Steady::now() > giveUp) {
        stop = true;
        reader.join();
        recording.check();
        throw std::runtime_error("no Start of Frame from " + options.igAddress + ":" + std::to_string(options.igPort) +
                                 " within " + std::to_string(options.waitForIgS) + " s");
      }
      message.start(cigi::IgControl{});
      send(message.bytes());
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    const std::lock_guard lock(mutex);
    report = ScriptedHostReport{};  // the figures are of the flight
    report.otherStartOfFrames.assign(others.size(), 0);
    sofIntervals.clear();
    sofArrivals.clear();
    for (auto& arrivals : otherSofArrivals) arrivals.clear();
  }
  const Steady::time_point start = Steady::now();
  report.flightStartNs = std::chrono::duration_cast<std::chrono::nanoseconds>(start.time_since_epoch()).count();
  const auto frames = static_cast<std::uint64_t>(std::llround(options.durationS * options.rateHz));
  for (std::uint64_t frame = 0; frame < frames; ++frame) {
    const double t = static_cast<double>(frame) / options.rateHz;
    std::this_thread::sleep_until(start + std::chrono::duration_cast<Steady::duration>(std::chrono::duration<double>(
                                              t + unit(random) * options.jitterMs * 1e-3)));
    const bool silent =
        options.silentFromS >= 0 && t >= options.silentFromS && t < options.silentFromS + options.silentForS;
    if (silent || unit(random) < options.lossFraction) {
      ++report.framesDropped;
      continue;
    }
    const Pose pose = flight.poseAtSeconds(t);
    const glm::dvec3 velocity = flight.velocityAtSeconds(t);
    const std::optional<core::GeodeticPosition> where = georeference.toGeodetic(pose.positionM);
    if (!where)
      throw std::runtime_error("the flight leaves the georeference's domain at t = " + std::to_string(t) + " s");

    cigi::IgControl control;
    control.extrapolationEnabled = options.extrapolation;
    control.hostFrameNumber = static_cast<std::uint32_t>(frame);
    control.timestampValid = true;
    control.timestampTicks = static_cast<std::uint32_t>(std::llround((t + options.clockOffsetS) / 10e-6));
    message.start(control);
    cigi::EntityControl ownship;
    ownship.entityId = 0;
    ownship.latitudeDegOrXM = where->latitudeDeg;
    ownship.longitudeDegOrYM = where->longitudeDeg;
    ownship.altitudeMOrZM = where->altitudeM;
    ownship.yawDeg = static_cast<float>(degrees(pose.headingRad));
    ownship.pitchDeg = static_cast<float>(degrees(pose.pitchRad));
    ownship.rollDeg = static_cast<float>(degrees(pose.rollRad));
    ownship.extrapolationEnabled = options.extrapolation;
    message.add(ownship);
    cigi::RateControl rates;  // world frame: north, east, down
    rates.xRateMps = static_cast<float>(velocity.y);
    rates.yRateMps = static_cast<float>(velocity.x);
    rates.zRateMps = static_cast<float>(-velocity.z);
    // The attitude's rates, as the IG reads them (rates of heading, pitch and roll), by central
    // difference over ±1 ms: a host without them makes the IG hold the attitude between frames.
    const double h = 1e-3;
    const Pose before = flight.poseAtSeconds(std::max(0.0, t - h)), after = flight.poseAtSeconds(t + h);
    const double span = t + h - std::max(0.0, t - h);
    const auto rateDegps = [span](double from, double to) {
      return static_cast<float>(degrees(std::remainder(to - from, 2.0 * std::numbers::pi)) / span);
    };
    rates.yawRateDegps = rateDegps(before.headingRad, after.headingRad);
    rates.pitchRateDegps = rateDegps(before.pitchRad, after.pitchRad);
    rates.rollRateDegps = rateDegps(before.rollRad, after.rollRad);
    message.add(rates);
    const auto framesPerSecond = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::lround(options.rateHz)));
    if (options.timeOfDay && frame % framesPerSecond == 0) message.add(*options.timeOfDay);
    if (options.requestHeights) {
      cigi::HatHotRequest request;
      request.hatHotId = static_cast<std::uint16_t>(frame);
      request.requestType = cigi::HatHotRequestType::HeightOfTerrain;
      request.latitudeDegOrXM = where->latitudeDeg;
      request.longitudeDegOrYM = where->longitudeDeg;
      request.altitudeMOrZM = where->altitudeM;
      message.add(request);
      const std::lock_guard lock(mutex);
      pending[request.hatHotId] = PendingHeight{pose.positionM, Steady::now()};
    }
    if (options.requestLineOfSight) {
      // To a point ahead on the heading, swinging above and below the terrain there (our best
      // resident level's height is good enough to aim with).
      const glm::dvec3 ahead{std::sin(pose.headingRad), std::cos(pose.headingRad), 0.0};
      glm::dvec3 to = pose.positionM + kLosAheadM * ahead;
      to.z = terrain.heightAtM(to.x, to.y, 0) +
             kLosSwingM * std::cos(2.0 * std::numbers::pi * static_cast<double>(frame) / kLosSwingPeriodFrames);
      if (const std::optional<core::GeodeticPosition> destination = georeference.toGeodetic(to)) {
        cigi::LosSegmentRequest request;
        request.losId = static_cast<std::uint16_t>(frame);
        request.requestType = frame % 2 == 0 ? cigi::LosRequestType::Basic : cigi::LosRequestType::Extended;
        request.sourceLatitudeDegOrXM = where->latitudeDeg;
        request.sourceLongitudeDegOrYM = where->longitudeDeg;
        request.sourceAltitudeMOrZM = where->altitudeM;
        request.destinationLatitudeDegOrXM = destination->latitudeDeg;
        request.destinationLongitudeDegOrYM = destination->longitudeDeg;
        request.destinationAltitudeMOrZM = destination->altitudeM;
        message.add(request);
        ++report.losRequests;
        const std::lock_guard lock(mutex);
        pendingLos[request.losId] = PendingLos{pose.positionM, to, Steady::now()};
      }
    }
    if (send(message.bytes()) < 0) {
      throw std::runtime_error("sending to " + options.igAddress + ":" + std::to_string(options.igPort) + ": " +
                               std::strerror(errno));
    }
    recording.sentOwnship(control.hostFrameNumber, ownship);
    ++report.framesSent;
  }
  report.flightEndNs = std::chrono::duration_cast<std::chrono::nanoseconds>(Steady::now().time_since_epoch()).count();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the last answers
  stop = true;
  reader.join();
  recording.check();

  // The reference: the same bilinear surface at full resolution, its tiles loaded first.
  std::vector<double> heightErrors;
  for (const auto& [pointM, heightM] : answers) {
    for (const glm::ivec2& t : core::lineOfSightTiles(terrain.geometry(), pointM, pointM)) {
      if (terrain.view().tile(0, t.x, t.y) == nullptr) terrain.request(0, t.x, t.y);
    }
    terrain.waitIdle(std::chrono::seconds(5));
    heightErrors.push_back(std::abs(heightM - terrain.heightAtM(pointM.x, pointM.y, 0)));
  }
  if (!sofIntervals.empty()) report.startOfFrameRateHz = 1.0 / percentile(sofIntervals, 0.5);
  std::vector<double> sharedSpreadsMs;
  for (const auto& arrivals : otherSofArrivals) {
    for (const auto& [frame, arrival] : arrivals) {
      const auto measured = sofArrivals.find(frame);
      if (measured == sofArrivals.end()) continue;
      sharedSpreadsMs.push_back(
          std::abs(std::chrono::duration<double, std::milli>(arrival - measured->second).count()));
    }
  }
  report.sharedFrameNumbers = sharedSpreadsMs.size();
  report.otherSendErrors = otherSendErrors.load();
  report.sharedFrameArrivalSpreadP99Ms = percentile(sharedSpreadsMs, 0.99);
  report.heightErrorMaxM = heightErrors.empty() ? 0.0 : *std::max_element(heightErrors.begin(), heightErrors.end());
  report.heightErrorP95M = percentile(heightErrors, 0.95);
  report.answerLatencyP50Ms = percentile(latenciesMs, 0.5);
  report.answerLatencyP99Ms = percentile(latenciesMs, 0.99);

  // LOS: our own march along the same segments, over the same level-0 surface.
  std::vector<double> rangeErrors;
  for (const LosAnswer& answer : losAnswers) {
    loadLevelZero(terrain, answer.fromM, answer.toM);
    const std::optional<double> rangeM = referenceSegmentRangeM(terrain.view(), answer.fromM, answer.toM);
    if (rangeM) ++report.losReferenceHits;
    if (rangeM.has_value() != answer.hit) {
      ++report.losDisagreements;
    } else if (rangeM) {
      rangeErrors.push_back(std::abs(answer.rangeM - *rangeM));
    }
  }
  report.losRangeErrorMaxM = rangeErrors.empty() ? 0.0 : *std::max_element(rangeErrors.begin(), rangeErrors.end());
  report.losRangeErrorP95M = percentile(rangeErrors, 0.95);
  report.losLatencyP50Ms = percentile(losLatenciesMs, 0.5);
  report.losLatencyP99Ms = percentile(losLatenciesMs, 0.99);
  return report;
}

std::string describe(const ScriptedHostReport& r) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(3);
  s << "host frames sent " << r.framesSent << " (dropped " << r.framesDropped << ")\n"
    << "start of frames " << r.startOfFrames << " at " << r.startOfFrameRateHz << " Hz (median interval), "
    << r.ownshipHeldFrames << " with the ownship held\n"
    << "HAT/HOT answers " << r.heightAnswers << " (" << r.heightAnswersValid << " valid), height error max "
    << r.heightErrorMaxM << " m, p95 " << r.heightErrorP95M << " m\n"
    << "answer latency p50 " << r.answerLatencyP50Ms << " ms, p99 " << r.answerLatencyP99Ms << " ms\n";
  if (r.losRequests > 0) {
    s << "LOS answers " << r.losAnswers << " of " << r.losRequests << " (" << r.losHits
      << " hits; the host's march: " << r.losReferenceHits << " hits, " << r.losDisagreements
      << " disagreements), range error max " << r.losRangeErrorMaxM << " m, p95 " << r.losRangeErrorP95M << " m\n"
      << "LOS answer latency p50 " << r.losLatencyP50Ms << " ms, p99 " << r.losLatencyP99Ms << " ms\n";
  }
  for (std::size_t i = 0; i < r.otherStartOfFrames.size(); ++i)
    s << "start of frames from channel " << i + 2 << ": " << r.otherStartOfFrames[i] << "\n";
  if (r.otherSendErrors > 0) s << "datagrams the other channels refused: " << r.otherSendErrors << "\n";
  if (!r.otherStartOfFrames.empty()) {
    s << "frame numbers reported by the measured channel and another: " << r.sharedFrameNumbers
      << ", their Start of Frames " << r.sharedFrameArrivalSpreadP99Ms << " ms apart (p99)\n";
  }
  s << "rejected datagrams " << r.rejectedDatagrams << "\n";
  return s.str();
}

}  // namespace fieldcast::tools
