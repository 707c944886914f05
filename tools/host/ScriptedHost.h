#pragma once
// A CIGI 3.3 host that flies a scripted flight: every host frame it sends IG Control, the
// ownship's Entity Control (geodetic, through the database's georeference) and Rate Control, and
// a HAT/HOT request under the ownship (and, on request, a Line of Sight Segment request from the
// ownship to the ground ahead); it reads back the IG's Start of Frame messages and answers and
// measures them — Start of Frame rate, answer latency, height and range errors against its own
// query of the same terrain. On request it sets the IG's date and time of day. Faults on request: jitter, loss, byte
// swapping, a host clock offset, a silent spell. It can record both directions as a pcap capture and log what it sent.

#include <ig_core/Georeference.h>
#include <ig_core/TileCache.h>
#include <motion/ScriptedTrajectory.h>

#include <io_bridge/PcapWriter.h>
#include <io_bridge/cigi/Packets.h>

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace fieldcast::tools {

struct ScriptedHostOptions {
  std::string igAddress = "127.0.0.1";
  std::uint16_t igPort = 8004;
  /// More channels of a rig at the same address: every datagram goes to each of them as well
  /// (as multicast would on a LAN). Only the IG at igPort is measured (Start of Frame rate,
  /// answers); the others' Start of Frames are counted per channel.
  std::vector<std::uint16_t> otherIgPorts;
  std::uint16_t localPort = 0;  ///< where the IG's replies arrive (0: any free port)
  double rateHz = 60.0;
  double durationS = 20.0;
  double jitterMs = 0.0;       ///< each datagram leaves up to this late (uniform)
  double lossFraction = 0.0;   ///< share of host frames never sent
  bool byteSwapped = false;    ///< send in the other byte order
  double clockOffsetS = 0.0;   ///< added to the host's timestamps
  double silentFromS = -1.0;   ///< a silent spell: no datagram from here ...
  double silentForS = 0.0;     ///< ... for this long
  bool requestHeights = true;  ///< a HAT/HOT request under the ownship each frame
  bool extrapolation = true;   ///< IG Control's extrapolation/interpolation enable
  /// A Line of Sight Segment request each frame from the ownship to a point kLosAheadM ahead on
  /// its heading, kLosSwingM above or below the terrain there (the offset swings, so some segments
  /// meet the ground and some do not); every other one asks for the Extended Response.
  bool requestLineOfSight = false;
  double waitForIgS = 0.0;  ///< first send IG Control alone until the IG answers (or this long)
  /// When set: a Celestial Sphere Control (the date and time of day, the ephemeris model running)
  /// with the first host frame and once a second after.
  std::optional<io::cigi::CelestialSphereControl> timeOfDay;
  std::uint32_t seed = 1;
};

/// The LOS request's geometry (see ScriptedHostOptions::requestLineOfSight).
inline constexpr double kLosAheadM = 400.0;
inline constexpr double kLosSwingM = 60.0;
inline constexpr int kLosSwingPeriodFrames = 45;

/// Where to record the exchange; null members record nothing. Written from the sending and the
/// receiving thread.
struct ScriptedHostRecorders {
  /// Every datagram sent and received, with its real addresses and ports, stamped with the wall
  /// clock when it was sent or received.
  io::PcapWriter* capture = nullptr;
  /// One line per host frame sent (header line first): host frame number, then the ownship's
  /// latitude, longitude, altitude, yaw, pitch, roll exactly as they went into Entity Control.
  std::ostream* sentLog = nullptr;
};

/// What came back. Heights and LOS ranges are compared with the host's own query of the same terrain.
struct ScriptedHostReport {
  std::uint64_t framesSent = 0;
  std::uint64_t framesDropped = 0;  ///< by lossFraction or the silent spell
  std::uint64_t startOfFrames = 0;
  double startOfFrameRateHz = 0.0;      ///< median over the run
  std::uint64_t ownshipHeldFrames = 0;  ///< Start of Frames whose IG status said the ownship was held
  std::uint64_t heightAnswers = 0;
  std::uint64_t heightAnswersValid = 0;
  double heightErrorMaxM = 0.0;
  double heightErrorP95M = 0.0;
  double answerLatencyP50Ms = 0.0;  ///< request sent → answer received
  double answerLatencyP99Ms = 0.0;
  std::uint64_t losRequests = 0;       ///< LOS Segment requests sent
  std::uint64_t losAnswers = 0;        ///< LOS Responses and Extended Responses to our requests
  std::uint64_t losHits = 0;           ///< ... that met the terrain (valid)
  std::uint64_t losReferenceHits = 0;  ///< requests answered whose segment meets the terrain by our march
  std::uint64_t losDisagreements = 0;  ///< answers that hit where our march does not, or the reverse
  double losRangeErrorMaxM = 0.0;      ///< |IG range − our march's range| over answers both call hits
  double losRangeErrorP95M = 0.0;
  double losLatencyP50Ms = 0.0;  ///< LOS request sent → answer received
  double losLatencyP99Ms = 0.0;
  std::uint64_t rejectedDatagrams = 0;
  /// Start of Frames from each of options.otherIgPorts, in that order (the measured IG at igPort
  /// is channel 1 in the report, these channels 2, 3, ...).
  std::vector<std::uint64_t> otherStartOfFrames;
  std::uint64_t otherSendErrors = 0;  ///< datagrams to the other channels the socket refused (one not running yet)
  /// A frame-locked rig's check from the host's side: of the IG frame numbers (field numbers) both
  /// the measured IG and another channel reported, how many, and how far apart (p99, ms) their
  /// Start of Frames arrived. Channels locked to one field epoch report field k together.
  std::uint64_t sharedFrameNumbers = 0;
  double sharedFrameArrivalSpreadP99Ms = 0.0;
  /// CLOCK_MONOTONIC instant of flight time 0 (steady_clock is CLOCK_MONOTONIC on Linux): the
  /// flight's pose at IG instant t is flight.poseAtSeconds((t - flightStartNs) / 1e9).
  std::int64_t flightStartNs = 0;
  /// When the flight's last frame had been sent (same clock): the flight's end as the IGs saw it
  std::int64_t flightEndNs = 0;
};

/// Plays `flight` as the host of the IG at options.igAddress:igPort. `terrain` is the database the
/// IG renders (for the reference heights and ranges), `georeference` its placement on the Earth.
/// Throws std::runtime_error on a socket or recording failure.
ScriptedHostReport runScriptedHost(const ScriptedHostOptions& options, const motion::ScriptedTrajectory& flight,
                                   core::TileCache& terrain, const core::Georeference& georeference,
                                   const ScriptedHostRecorders& recorders = {});

/// The report as a few lines for people.
std::string describe(const ScriptedHostReport& report);

}  // namespace fieldcast::tools
