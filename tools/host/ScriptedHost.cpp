#include "ScriptedHost.h"

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
#include <cstring>
#include <map>
#include <mutex>
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

 private:
  int mFd = -1;
};

// A request in flight: where it asked and when it left.
struct PendingHeight {
  glm::dvec3 pointM;
  Steady::time_point sent;
};

}  // namespace

ScriptedHostReport runScriptedHost(const ScriptedHostOptions& options, const motion::ScriptedTrajectory& flight,
                                   core::TileCache& terrain, const core::Georeference& georeference) {
  sockaddr_in ig{};
  ig.sin_family = AF_INET;
  ig.sin_port = htons(options.igPort);
  if (inet_pton(AF_INET, options.igAddress.c_str(), &ig.sin_addr) != 1) {
    throw std::runtime_error("--ig: '" + options.igAddress + "' is not an IPv4 address");
  }
  Socket socket(options.localPort);

  std::mutex mutex;  // guards pending, the report's lists and counters shared with the reader
  std::map<std::uint16_t, PendingHeight> pending;
  std::vector<double> sofIntervals, latenciesMs;
  std::vector<std::pair<glm::dvec3, double>> answers;  // where a valid answer was asked, and its height
  ScriptedHostReport report;
  std::atomic<bool> stop{false};
  std::atomic<bool> heard{false};  // a Start of Frame has arrived

  // The reader: Start of Frames and answers, timed on arrival.
  std::thread reader([&] {
    cigi::IgDatagramDecoder decoder;
    std::vector<cigi::IgPacket> packets;
    std::vector<std::uint8_t> buffer(cigi::kMaxDatagramBytes);
    std::optional<Steady::time_point> lastSof;
    while (!stop.load()) {
      pollfd fd{socket.fd(), POLLIN, 0};
      if (::poll(&fd, 1, 50) <= 0) continue;
      const ssize_t n = ::recv(socket.fd(), buffer.data(), buffer.size(), 0);
      if (n <= 0) continue;
      const Steady::time_point arrival = Steady::now();
      if (!decoder.decode(std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n)), packets)) continue;
      const std::lock_guard lock(mutex);
      for (const cigi::IgPacket& packet : packets) {
        if (const auto* sof = std::get_if<cigi::StartOfFrame>(&packet)) {
          ++report.startOfFrames;
          heard = true;
          if (sof->igStatus != 0) ++report.ownshipHeldFrames;
          if (lastSof) sofIntervals.push_back(std::chrono::duration<double>(arrival - *lastSof).count());
          lastSof = arrival;
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
        throw std::runtime_error("no Start of Frame from " + options.igAddress + ":" + std::to_string(options.igPort) +
                                 " within " + std::to_string(options.waitForIgS) + " s");
      }
      message.start(cigi::IgControl{});
      const std::span<const std::uint8_t> bytes = message.bytes();
      ::sendto(socket.fd(), bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&ig), sizeof ig);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    const std::lock_guard lock(mutex);
    report = ScriptedHostReport{};  // the figures are of the flight
    sofIntervals.clear();
  }
  const Steady::time_point start = Steady::now();
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
    message.add(ownship);
    cigi::RateControl rates;  // world frame: north, east, down
    rates.xRateMps = static_cast<float>(velocity.y);
    rates.yRateMps = static_cast<float>(velocity.x);
    rates.zRateMps = static_cast<float>(-velocity.z);
    message.add(rates);
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
    const std::span<const std::uint8_t> bytes = message.bytes();
    if (::sendto(socket.fd(), bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&ig), sizeof ig) < 0) {
      throw std::runtime_error("sending to " + options.igAddress + ":" + std::to_string(options.igPort) + ": " +
                               std::strerror(errno));
    }
    ++report.framesSent;
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the last answers
  stop = true;
  reader.join();

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
  report.heightErrorMaxM = heightErrors.empty() ? 0.0 : *std::max_element(heightErrors.begin(), heightErrors.end());
  report.heightErrorP95M = percentile(heightErrors, 0.95);
  report.answerLatencyP50Ms = percentile(latenciesMs, 0.5);
  report.answerLatencyP99Ms = percentile(latenciesMs, 0.99);
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
    << "answer latency p50 " << r.answerLatencyP50Ms << " ms, p99 " << r.answerLatencyP99Ms << " ms\n"
    << "rejected datagrams " << r.rejectedDatagrams << "\n";
  return s.str();
}

}  // namespace fieldcast::tools
