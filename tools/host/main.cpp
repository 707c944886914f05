// fieldcast-host — a scripted CIGI 3.3 host: flies a flight file as the host of a Fieldcast IG
// (or any IG) over UDP, and reports what the IG sent back.
//   fieldcast-host --config config/host.toml --flight config/flights/ridge_run.toml --duration 20
//   fieldcast-host --flight config/flights/ridge_run.toml --los --pcap out/host.pcap --sent-log out/sent.tsv
// The configuration is the IG's own (its [terrain] and [host] sections): the host places the
// flight on the Earth through the same georeference and checks the IG's heights and line-of-sight
// ranges against the same terrain (its own fine march: LosReference.h).
//   --los            a Line of Sight Segment request each frame, to the ground ahead and below
//   --pcap FILE      both directions as a classic pcap capture (Wireshark: decode the IG's port as CIGI)
//   --sent-log FILE  the ownship's Entity Control values of each host frame sent, tab-separated
//   --time-of-day 2024-06-21T19:30   the date and time of day (Celestial Sphere Control), running
//   --also-ig-port 8006   another channel of a rig at the same address: every datagram to it too
#include "ScriptedHost.h"

#include <service/ServiceConfig.h>
#include <tools/OptionChecks.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace {

// "2024-06-21T19:30" as a Celestial Sphere Control: date and time valid, the ephemeris model
// running, the sun on. Nothing when the text is not of that form (the IG judges the date itself).
std::optional<fieldcast::io::cigi::CelestialSphereControl> celestialControlOf(const std::string& text) {
  int year = 0, month = 0, day = 0, hour = 0, minute = 0, used = 0;
  if (std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d%n", &year, &month, &day, &hour, &minute, &used) != 5 ||
      used != static_cast<int>(text.size()) || year < 1 || month < 1 || month > 12 || day < 1 || day > 31 ||
      hour > 23 || minute > 59 || hour < 0 || minute < 0) {
    return std::nullopt;
  }
  fieldcast::io::cigi::CelestialSphereControl c;
  c.hour = static_cast<std::uint8_t>(hour);
  c.minute = static_cast<std::uint8_t>(minute);
  c.dateMMDDYYYY = static_cast<std::uint32_t>(month * 1000000 + day * 10000 + year);
  c.dateTimeValid = true;
  c.ephemerisModelEnabled = true;
  c.sunEnabled = true;
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace fieldcast;
  CLI::App app("fieldcast-host: a scripted CIGI 3.3 host for a Fieldcast IG");
  std::string configPath = FIELDCAST_DEFAULT_CONFIG;
  std::string flightPath;
  std::string summaryPath;
  std::string pcapPath;
  std::string sentLogPath;
  std::string ig = "127.0.0.1";
  tools::ScriptedHostOptions options;
  int igPort = -1;
  app.add_option("--config", configPath, "the IG's configuration ([terrain], [host])")->check(CLI::ExistingFile);
  app.add_option("--flight", flightPath, "flight file to fly (config/flights/*.toml)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--ig", ig, "the IG's IPv4 address");
  app.add_option("--ig-port", igPort, "the IG's port (default: host.port of the configuration)")
      ->check(tools::intRange(1, 65535, ""));
  app.add_option("--also-ig-port", options.otherIgPorts,
                 "another channel of a rig at the same address: it gets every datagram too (repeatable)")
      ->check(tools::intRange(1, 65535, ""));
  app.add_option("--port", options.localPort, "this host's port for the IG's replies (0: any)")
      ->check(tools::intRange(0, 65535, ""));
  app.add_option("--rate", options.rateHz, "host frames per second")->check(tools::finiteRange(1, 1000, "Hz"));
  app.add_option("--duration", options.durationS, "seconds to fly")->check(tools::finiteRange(0.1, 1e6, "s"));
  app.add_option("--jitter-ms", options.jitterMs, "each datagram leaves up to this late")
      ->check(tools::finiteRange(0, 1000, "ms"));
  app.add_option("--loss", options.lossFraction, "share of host frames not sent")->check(tools::finiteRange(0, 1, ""));
  app.add_flag("--swap", options.byteSwapped, "send in the other byte order");
  app.add_option("--clock-offset", options.clockOffsetS, "added to the host timestamps, seconds")
      ->check(tools::finiteRange(-40000, 40000, "s"));
  app.add_option("--silent-from", options.silentFromS, "fall silent at this flight time, seconds")
      ->check(tools::finiteRange(0, 1e6, "s"));
  app.add_option("--silent-for", options.silentForS, "... for this long, seconds")
      ->check(tools::finiteRange(0, 1e6, "s"));
  app.add_option("--wait-for-ig", options.waitForIgS, "first wait this long for the IG to answer, seconds")
      ->check(tools::finiteRange(0, 3600, "s"));
  app.add_flag("!--no-heights", options.requestHeights, "do not request HAT/HOT each frame");
  app.add_flag("!--no-extrapolation", options.extrapolation,
               "clear IG Control's extrapolation/interpolation enable: the IG shows each pose as sent");
  app.add_flag("--los", options.requestLineOfSight,
               "request line of sight each frame to the ground ahead and check the ranges");
  std::string timeOfDay;
  app.add_option("--time-of-day", timeOfDay,
                 "send this date and time (YYYY-MM-DDTHH:MM, the IG's celestial_utc_offset_h time zone), running")
      ->check([](const std::string& text) -> std::string {
        return celestialControlOf(text) ? "" : "expected YYYY-MM-DDTHH:MM, e.g. 2024-06-21T19:30";
      });
  app.add_option("--pcap", pcapPath, "record every datagram sent and received as a pcap file");
  app.add_option("--sent-log", sentLogPath, "log the ownship values sent each host frame (tab-separated)");
  app.add_option("--summary", summaryPath, "write the report as JSON here");
  CLI11_PARSE(app, argc, argv);
  options.igAddress = ig;
  if (!timeOfDay.empty()) options.timeOfDay = celestialControlOf(timeOfDay);

  try {
    // The recordings are opened first, so an unwritable path fails at once.
    for (const std::string& path : {pcapPath, sentLogPath}) {
      std::error_code ignored;  // a directory that cannot be made shows as the file's error below
      if (!path.empty()) std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ignored);
    }
    std::unique_ptr<io::PcapWriter> capture;
    if (!pcapPath.empty()) {
      try {
        capture = std::make_unique<io::PcapWriter>(pcapPath);
      } catch (const std::exception& e) {
        throw std::runtime_error(std::string("--pcap: ") + e.what());
      }
    }
    std::ofstream sentLog;
    if (!sentLogPath.empty()) {
      sentLog.open(sentLogPath);
      if (!sentLog) throw std::runtime_error("--sent-log: " + sentLogPath + ": cannot create the file");
    }
    const app::ServiceConfig config = app::loadServiceConfig(configPath);
    options.igPort = igPort > 0 ? static_cast<std::uint16_t>(igPort) : config.host.link.port;
    const motion::ScriptedTrajectory flight = motion::ScriptedTrajectory::load(flightPath);
    std::unique_ptr<core::TileCache> terrain = core::openTerrain(config.terrain);
    const core::Georeference georeference = core::Georeference::forTerrain(terrain->crs(), config.host.origin);
    const tools::ScriptedHostRecorders recorders{capture.get(), sentLogPath.empty() ? nullptr : &sentLog};
    std::printf("host: flying %s for %.1f s at %.1f Hz to %s:%u (%s)\n", flightPath.c_str(), options.durationS,
                options.rateHz, options.igAddress.c_str(), options.igPort, georeference.description().c_str());
    const tools::ScriptedHostReport report = tools::runScriptedHost(options, flight, *terrain, georeference, recorders);
    std::fputs(tools::describe(report).c_str(), stdout);
    if (!summaryPath.empty()) {
      nlohmann::json j;
      j["host_frames_sent"] = report.framesSent;
      j["host_frames_dropped"] = report.framesDropped;
      j["start_of_frames"] = report.startOfFrames;
      j["start_of_frame_rate_hz"] = report.startOfFrameRateHz;
      j["ownship_held_frames"] = report.ownshipHeldFrames;
      j["height_answers"] = report.heightAnswers;
      j["height_answers_valid"] = report.heightAnswersValid;
      j["height_error_max_m"] = report.heightErrorMaxM;
      j["height_error_p95_m"] = report.heightErrorP95M;
      j["answer_latency_p50_ms"] = report.answerLatencyP50Ms;
      j["answer_latency_p99_ms"] = report.answerLatencyP99Ms;
      j["los_requests"] = report.losRequests;
      j["los_answers"] = report.losAnswers;
      j["los_hits"] = report.losHits;
      j["los_reference_hits"] = report.losReferenceHits;
      j["los_disagreements"] = report.losDisagreements;
      j["los_range_error_max_m"] = report.losRangeErrorMaxM;
      j["los_range_error_p95_m"] = report.losRangeErrorP95M;
      j["los_latency_p50_ms"] = report.losLatencyP50Ms;
      j["los_latency_p99_ms"] = report.losLatencyP99Ms;
      j["pcap_frames"] = capture ? capture->frames() : 0;
      j["rejected_datagrams"] = report.rejectedDatagrams;
      j["other_channels_start_of_frames"] = report.otherStartOfFrames;
      j["shared_frame_numbers"] = report.sharedFrameNumbers;
      j["other_channels_send_errors"] = report.otherSendErrors;
      j["shared_frame_arrival_spread_p99_ms"] = report.sharedFrameArrivalSpreadP99Ms;
      j["flight_start_monotonic_ns"] = report.flightStartNs;
      j["flight_end_monotonic_ns"] = report.flightEndNs;
      std::ofstream out(summaryPath);
      out << j.dump(2) << "\n";
      if (!out) throw std::runtime_error("--summary: cannot write " + summaryPath);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fieldcast-host: %s\n", e.what());
    return 1;
  }
  return 0;
}
