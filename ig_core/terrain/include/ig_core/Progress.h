#pragma once
// Progress of long offline jobs (building the built-in terrain, importing a DEM).

#include <chrono>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>

namespace fieldcast::core {

/// Called with the stage being worked on and the fraction of it done, in [0, 1]. May be called
/// from several threads; the callee serialises. An empty function reports nothing.
using ProgressFn = std::function<void(std::string_view stage, double fraction)>;

/// Shows a job's progress the way its user can see it: a redrawn bar on stderr when stderr is a
/// terminal, otherwise one quiet log line when each stage starts (CI logs stay short).
class ConsoleProgress {
 public:
  /// `job` names the whole job in the bar and the log ("built-in terrain 8192x8192").
  explicit ConsoleProgress(std::string job);
  ~ConsoleProgress();
  ConsoleProgress(const ConsoleProgress&) = delete;
  ConsoleProgress& operator=(const ConsoleProgress&) = delete;

  /// Reports progress; thread-safe, redraws at most every 100 ms.
  void report(std::string_view stage, double fraction);
  /// A ProgressFn that forwards to this object (which must outlive it).
  ProgressFn callback() {
    return [this](std::string_view stage, double fraction) { report(stage, fraction); };
  }

 private:
  std::string mJob;
  bool mTerminal = false;
  std::mutex mMutex;
  std::string mStage;
  std::chrono::steady_clock::time_point mStart;
  std::chrono::steady_clock::time_point mLastDraw;
  bool mDrawn = false;
};

}  // namespace fieldcast::core
