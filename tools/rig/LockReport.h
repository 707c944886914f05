#pragma once
// How well the channels of a rig were locked, from their own records: for every field number
// all of them made, how far apart their display times and their emission instants were, and
// whether they showed the same instant of the ownship's motion.

#include "ChannelRun.h"
#include "MachineStalls.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace fieldcast::tools {

struct Spread {
  double p50 = 0, p99 = 0, max = 0;
};

/// The host's flight as it reported it (fieldcast-host --summary): the instants it sent its first
/// frame and had sent its last, on the channels' clock.
struct FlightWindow {
  std::int64_t beginNs = 0, endNs = 0;
};

struct LockReport {
  std::uint64_t commonFields = 0;  ///< field numbers every channel made
  Spread displayMs;                ///< max − min of the channels' display times of field k
  Spread emittedMs;                ///< max − min of when they handed field k to their outputs
  /// How far apart the channels' eye positions were at one field: over the fields every channel
  /// made from a host sample (all fields when there was no host)
  Spread positionM;
  std::uint64_t positionFields = 0;  ///< the fields compared for positionM
  std::uint64_t sameHostFrame = 0;   ///< common fields whose pose every channel made from the same host sample
  std::uint64_t partlyHosted = 0;    ///< common fields some channels made from a host sample, others not yet
  struct PerChannel {
    std::string name;
    std::uint64_t fields = 0, missed = 0, black = 0, firstField = 0, lastField = 0, relocks = 0;
    int fieldCpu = -1;                                   ///< the CPU its field thread was pinned to; −1: not pinned
    std::int64_t firstDisplayNs = 0, lastDisplayNs = 0;  ///< of the first and last logged fields
    /// The first field of the flight: displayed from the host's first frame on (without the
    /// host's instants, the first field made from a host sample); firstField without a host.
    std::uint64_t flightFirstField = 0;
    std::uint64_t missedInFlight = 0;              ///< missed during the flight (the rest: before or after it)
    std::uint64_t missedInFlightDuringStalls = 0;  ///< ... of them, explained by a stall of the machine itself
    std::vector<std::uint64_t> excusedFields;      ///< ... their numbers
    double latestEmissionMs = 0;       ///< the latest any field was handed over, from its display time (< 0: before it)
    std::uint64_t handedOverLate = 0;  ///< fields handed to the outputs after their display time
  };
  std::vector<PerChannel> channels;
  std::uint64_t machineStalls = 0;  ///< the stall probe's records (0 without one)
  double longestStallMs = 0;        ///< the longest of them
  std::optional<FlightWindow> flight;
};

/// `stalls`: what fieldcast-stall-probe recorded over the run, if it ran; `flight`: the host's.
LockReport lockReport(const std::vector<ChannelRun>& channels, const std::vector<MachineStall>& stalls = {},
                      std::optional<FlightWindow> flight = std::nullopt);

/// What a locked rig must show (README "Channels"): every channel made every field while the
/// host flew (`allowedMissed` excepted, for a machine shared with other work; fields missed
/// before, while channels were still starting, and fields a stall of the machine itself
/// explains are reported, not failed) and ran to the flight's end, none black, none moved onto
/// another lock, field k's display time the same in every channel (spread p99 at most 0.5 ms),
/// and fields in common. One line per failure; empty: locked.
std::vector<std::string> lockFailures(const LockReport& report, std::uint64_t allowedMissed = 0);

nlohmann::json toJson(const LockReport& report);
/// A few lines for people.
std::string describe(const LockReport& report);

}  // namespace fieldcast::tools
