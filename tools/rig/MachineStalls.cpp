// The stall probe's file, and which field a stall explains.
#include "MachineStalls.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace fieldcast::tools {
namespace {
constexpr const char* kHeader = "cpu,due_ns,woke_ns";
}

std::vector<MachineStall> readMachineStalls(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot read (fieldcast-stall-probe's --out)");
  std::string line;
  if (!std::getline(in, line) || line != kHeader)
    throw std::runtime_error(path.string() + ": expected the header line \"" + kHeader + "\"");
  std::vector<MachineStall> stalls;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    std::istringstream cells(line);
    MachineStall s;
    char comma1 = 0, comma2 = 0;
    cells >> s.cpu >> comma1 >> s.dueNs >> comma2 >> s.wokeNs;
    if (!cells || comma1 != ',' || comma2 != ',' || !(cells >> std::ws).eof() || s.cpu < 0 || s.wokeNs < s.dueNs)
      throw std::runtime_error(path.string() + ":" + std::to_string(number) + ": expected cpu,due_ns,woke_ns, got " +
                               line);
    stalls.push_back(s);
  }
  return stalls;
}

void writeMachineStalls(const std::filesystem::path& path, const std::vector<MachineStall>& stalls) {
  std::ofstream out(path);
  out << kHeader << "\n";
  for (const MachineStall& s : stalls) out << s.cpu << ',' << s.dueNs << ',' << s.wokeNs << "\n";
  if (!out.flush()) throw std::runtime_error(path.string() + ": cannot write");
}

namespace {
constexpr std::int64_t kLeastWorkNs = 1'000'000;    // warp::FieldClock's minimum work before a field
constexpr std::int64_t kProbePeriodNs = 1'000'000;  // fieldcast-stall-probe's period (rig.sh's)
// Two warps: two field threads share a CPU in the rig and both run when it comes back (a warp
// here takes up to 5 ms, the summaries' warp_time)
constexpr std::int64_t kAfterStallNs = 10'000'000;
}  // namespace

namespace {

// The windows of stallAround (any CPU), those that overlap merged, in time order.
std::vector<std::pair<std::int64_t, std::int64_t>> mergedStallWindows(const std::vector<MachineStall>& stalls) {
  std::vector<std::pair<std::int64_t, std::int64_t>> windows;
  for (const MachineStall& s : stalls) windows.emplace_back(s.dueNs - kProbePeriodNs, s.wokeNs + kAfterStallNs);
  std::sort(windows.begin(), windows.end());
  std::vector<std::pair<std::int64_t, std::int64_t>> merged;
  for (const auto& w : windows) {
    if (!merged.empty() && w.first <= merged.back().second)
      merged.back().second = std::max(merged.back().second, w.second);
    else
      merged.push_back(w);
  }
  return merged;
}

}  // namespace

int fieldsDueInStalls(const std::vector<MachineStall>& stalls, std::int64_t fieldPeriodNs) {
  int fields = 0;
  for (const auto& [from, to] : mergedStallWindows(stalls))
    fields += static_cast<int>((to - from) / fieldPeriodNs) + 1;  // deadlines one period apart
  return fields;
}

std::int64_t stalledNsBetween(const std::vector<MachineStall>& stalls, std::int64_t fromNs, std::int64_t toNs) {
  std::int64_t stalled = 0;
  for (const auto& [from, to] : mergedStallWindows(stalls))
    stalled += std::max<std::int64_t>(0, std::min(to, toNs) - std::max(from, fromNs));
  return stalled;
}

const MachineStall* stallAround(const std::vector<MachineStall>& stalls, std::int64_t displayNs, int cpu) {
  const std::int64_t deadline = displayNs - kLeastWorkNs;
  for (const MachineStall& s : stalls) {
    if ((cpu < 0 || s.cpu == cpu) && deadline >= s.dueNs - kProbePeriodNs && deadline <= s.wokeNs + kAfterStallNs)
      return &s;
  }
  return nullptr;
}

}  // namespace fieldcast::tools
