#pragma once
// How well the channels of a rig were locked, from their own records: for every field number
// all of them made, how far apart their display times and their emission instants were, and
// whether they showed the same instant of the ownship's motion.

#include "ChannelRun.h"

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace fieldcast::tools {

struct Spread {
  double p50 = 0, p99 = 0, max = 0;
};

struct LockReport {
  std::uint64_t commonFields = 0;   ///< field numbers every channel made
  Spread displayMs;                 ///< max − min of the channels' display times of field k
  Spread emittedMs;                 ///< max − min of when they handed field k to their outputs
  double positionSpreadMaxM = 0;    ///< largest distance between the channels' eye positions at one field
  std::uint64_t sameHostFrame = 0;  ///< common fields whose pose every channel made from the same host sample
  struct PerChannel {
    std::string name;
    std::uint64_t fields = 0, missed = 0, black = 0, firstField = 0, lastField = 0, relocks = 0;
    double latestEmissionMs = 0;       ///< the latest any field was handed over, from its display time (< 0: before it)
    std::uint64_t handedOverLate = 0;  ///< fields handed to the outputs after their display time
  };
  std::vector<PerChannel> channels;
};

LockReport lockReport(const std::vector<ChannelRun>& channels);

/// What a locked rig must show (README "Channels"): every channel made every field of its run
/// (`allowedMissed` excepted, for a machine shared with other work) and none black, none moved
/// onto another lock, field k's display time the same in every channel (spread p99 at most
/// 0.5 ms), and fields in common. One line per failure; empty: locked.
std::vector<std::string> lockFailures(const LockReport& report, std::uint64_t allowedMissed = 0);

nlohmann::json toJson(const LockReport& report);
/// A few lines for people.
std::string describe(const LockReport& report);

}  // namespace fieldcast::tools
