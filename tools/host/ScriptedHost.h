#pragma once
// A CIGI 3.3 host that flies a scripted flight: every host frame it sends IG Control, the
// ownship's Entity Control (geodetic, through the database's georeference) and Rate Control, and
// a HAT/HOT request under the ownship; it reads back the IG's Start of Frame messages and answers
// and measures them — Start of Frame rate, answer latency, height error against its own terrain
// query. Faults on request: jitter, loss, byte swapping, a host clock offset, a silent spell.

#include <ig_core/Georeference.h>
#include <ig_core/TileCache.h>
#include <motion/ScriptedTrajectory.h>

#include <cstdint>
#include <string>

namespace fieldcast::tools {

struct ScriptedHostOptions {
  std::string igAddress = "127.0.0.1";
  std::uint16_t igPort = 8004;
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
  double waitForIgS = 0.0;     ///< first send IG Control alone until the IG answers (or this long)
  std::uint32_t seed = 1;
};

/// What came back. Heights are compared with the host's own query of the same terrain.
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
  std::uint64_t rejectedDatagrams = 0;
};

/// Plays `flight` as the host of the IG at options.igAddress:igPort. `terrain` is the database the
/// IG renders (for the reference heights), `georeference` its placement on the Earth.
ScriptedHostReport runScriptedHost(const ScriptedHostOptions& options, const motion::ScriptedTrajectory& flight,
                                   core::TileCache& terrain, const core::Georeference& georeference);

/// The report as a few lines for people.
std::string describe(const ScriptedHostReport& report);

}  // namespace fieldcast::tools
