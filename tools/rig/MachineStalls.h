#pragma once
// Stalls of the machine itself, as fieldcast-stall-probe records them: a SCHED_FIFO thread on
// each CPU that should wake every millisecond and woke late. A virtual machine's CPU that the
// hypervisor takes away for 100 ms stops every timer on it, the field threads' too; the rig's
// report tells a field missed then from one the IG missed by itself.

#include <cstdint>
#include <filesystem>
#include <vector>

namespace fieldcast::tools {

struct MachineStall {
  int cpu = 0;              ///< the CPU whose probe woke late
  std::int64_t dueNs = 0;   ///< when the probe should have woken (CLOCK_MONOTONIC)
  std::int64_t wokeNs = 0;  ///< when it did
  double lateMs() const { return static_cast<double>(wokeNs - dueNs) * 1e-6; }
};

/// The probe's file: a header line "cpu,due_ns,woke_ns", then one stall per line. Throws
/// std::runtime_error naming the file and line when it cannot be read or a line is malformed.
std::vector<MachineStall> readMachineStalls(const std::filesystem::path& path);
/// Writes `stalls` in that form; throws std::runtime_error when the file cannot be written.
void writeMachineStalls(const std::filesystem::path& path, const std::vector<MachineStall>& stalls);

/// The stall that cost the field shown at `displayNs`, if one did; nullptr otherwise. A field is
/// missed when its field thread has not started it by its display time less the field clock's
/// least work (1 ms): a stall explains it when that deadline falls in the stall, from a probe
/// period before the probe's missed wake-up to two warps' time (10 ms) after it woke — the
/// threads on that CPU first finish the fields they were on. `cpu`: the CPU the channel's field
/// thread is pinned to; −1 (not pinned): a stall on any CPU. Assumes the probe's period of 1 ms.
const MachineStall* stallAround(const std::vector<MachineStall>& stalls, std::int64_t displayNs, int cpu = -1);

/// How many fields of period `fieldPeriodNs` a stall explains at most: those whose deadline falls
/// in a window of stallAround (any CPU), the windows of overlapping stalls merged.
int fieldsDueInStalls(const std::vector<MachineStall>& stalls, std::int64_t fieldPeriodNs);

/// How much of the time from `fromNs` to `toNs` (CLOCK_MONOTONIC) the stalls' windows (those of
/// fieldsDueInStalls) cover: what a latency measured over that time may owe to the machine.
std::int64_t stalledNsBetween(const std::vector<MachineStall>& stalls, std::int64_t fromNs, std::int64_t toNs);

}  // namespace fieldcast::tools
