// fieldcast-rig — the figures and the contact sheet of a rig's run (scripts/rig.sh): reads each
// channel's folder (fields.csv, summary.json, images/), reports how well the channels were
// locked and stitches their fields side by side.
//   fieldcast-rig --channel left=out/rig/left --channel centre=out/rig/centre --channel right=out/rig/right
//                 --sheet out/rig/contact_sheet.png --report out/rig/report.json [--stalls out/rig/stalls.csv]
#include "ChannelRun.h"
#include "LockReport.h"
#include "StitchedSheet.h"

#include <tools/OptionChecks.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
  using namespace fieldcast;
  CLI::App app{"fieldcast-rig: the lock figures and the stitched contact sheet of a rig's channels"};
  std::vector<std::string> channelArgs;
  std::string sheetPath, reportPath, stallsPath, hostPath;
  std::vector<std::string> fieldCpuArgs;
  int rows = 8;
  bool check = false;
  std::uint64_t allowedMissed = 0;
  app.add_option("--channel", channelArgs, "NAME=FOLDER of a channel, left to right (repeatable)")->required();
  app.add_option("--sheet", sheetPath, "write the stitched contact sheet here (PNG)");
  app.add_option("--report", reportPath, "write the lock figures here (JSON)");
  app.add_option("--rows", rows, "instants on the sheet")->check(tools::intRange(1, 100, ""));
  app.add_flag("--check", check,
               "exit 1 unless the rig was locked: no field missed while the host flew (the machine's own stalls "
               "apart) or black, every log over the whole flight (with --host), one lock, field k's display time "
               "the same everywhere, no blank field on the sheet");
  app.add_option("--allow-missed", allowedMissed, "with --check: missed fields a channel may have (a shared machine)");
  app.add_option("--host", hostPath,
                 "the host's summary (fieldcast-host --summary): the flight is from its first frame to its last");
  app.add_option("--field-cpu", fieldCpuArgs,
                 "NAME=CPU: the CPU that channel's field thread was pinned to (threads.field_thread_cpu); only a stall "
                 "of that CPU explains its missed fields (repeatable; without: a stall of any CPU)");
  app.add_option("--stalls", stallsPath,
                 "the machine's stalls over the run (fieldcast-stall-probe --out): fields due during one are "
                 "reported apart, not failed");
  CLI11_PARSE(app, argc, argv);
  try {
    std::vector<tools::ChannelRun> channels;
    for (const std::string& arg : channelArgs) {
      const std::size_t equals = arg.find('=');
      if (equals == std::string::npos || equals == 0)
        throw std::runtime_error("--channel: expected NAME=FOLDER, got " + arg);
      channels.push_back(tools::readChannelRun(arg.substr(0, equals), arg.substr(equals + 1)));
    }
    for (const std::string& arg : fieldCpuArgs) {
      const std::size_t equals = arg.find('=');
      const auto channel = std::find_if(channels.begin(), channels.end(),
                                        [&](const tools::ChannelRun& c) { return c.name == arg.substr(0, equals); });
      int cpu = -1;
      if (equals == std::string::npos || channel == channels.end() ||
          !CLI::detail::lexical_cast(arg.substr(equals + 1), cpu) || cpu < 0)
        throw std::runtime_error("--field-cpu: expected NAME=CPU of a --channel, got " + arg);
      channel->fieldCpu = cpu;
    }
    std::optional<tools::FlightWindow> flight;
    if (!hostPath.empty()) {
      std::ifstream in(hostPath);
      nlohmann::json host;
      try {
        host = nlohmann::json::parse(in);
        flight = tools::FlightWindow{host.at("flight_start_monotonic_ns").get<std::int64_t>(),
                                     host.at("flight_end_monotonic_ns").get<std::int64_t>()};
      } catch (const std::exception& e) {
        throw std::runtime_error("--host " + hostPath + ": " + e.what());
      }
    }
    const std::vector<tools::MachineStall> stalls =
        stallsPath.empty() ? std::vector<tools::MachineStall>{} : tools::readMachineStalls(stallsPath);
    const tools::LockReport report = tools::lockReport(channels, stalls, flight);
    std::fputs(tools::describe(report).c_str(), stdout);
    if (!reportPath.empty()) {
      std::ofstream out(reportPath);
      out << tools::toJson(report).dump(2) << "\n";
      if (!out) throw std::runtime_error("--report: cannot write " + reportPath);
    }
    std::vector<std::string> failures = check ? tools::lockFailures(report, allowedMissed) : std::vector<std::string>{};
    if (!sheetPath.empty()) {
      const tools::SheetWritten written = tools::writeStitchedSheet(channels, sheetPath, rows);
      std::printf("wrote %s: %d instants of %zu channels, least contrast of a field %.1f grey levels\n",
                  sheetPath.c_str(), written.rows, channels.size(), written.leastContrast);
      if (check && written.leastContrast < 4.0)
        failures.push_back("a field on the sheet is blank (black or one colour)");
    }
    for (const std::string& failure : failures)
      std::fprintf(stderr, "fieldcast-rig: not locked: %s\n", failure.c_str());
    if (!failures.empty()) return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fieldcast-rig: %s\n", e.what());
    return 1;
  }
  return 0;
}
