#include <ig_core/Progress.h>

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>

namespace fieldcast::core {

ConsoleProgress::ConsoleProgress(std::string job)
    : mJob(std::move(job)), mTerminal(::isatty(STDERR_FILENO) == 1), mStart(std::chrono::steady_clock::now()) {
  if (!mTerminal) spdlog::info("{}: building", mJob);
}

ConsoleProgress::~ConsoleProgress() {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count();
  if (mTerminal && mDrawn) std::fputs("\n", stderr);
  // Destroyed while an exception unwinds: the job failed (its error is reported by the catcher).
  if (std::uncaught_exceptions() > 0) {
    spdlog::info("{}: stopped after {:.1f} s", mJob, seconds);
  } else if (!mTerminal) {
    spdlog::info("{}: done in {:.1f} s", mJob, seconds);
  }
}

void ConsoleProgress::report(std::string_view stage, double fraction) {
  const std::lock_guard lock(mMutex);
  const auto now = std::chrono::steady_clock::now();
  const bool newStage = stage != mStage;
  if (newStage) mStage = std::string(stage);
  if (!mTerminal) {
    if (newStage) spdlog::info("{}: {}", mJob, mStage);
    return;
  }
  if (!newStage && fraction < 1.0 && now - mLastDraw < std::chrono::milliseconds(100)) return;
  mLastDraw = now;
  mDrawn = true;
  constexpr int kWidth = 30;
  const double f = std::clamp(fraction, 0.0, 1.0);
  const int filled = static_cast<int>(f * kWidth + 0.5);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(kWidth, '.');
  const double seconds = std::chrono::duration<double>(now - mStart).count();
  std::fprintf(stderr, "\r%s: %-8s [%s] %3d%%  %5.1f s ", mJob.c_str(), mStage.c_str(), bar.c_str(),
               static_cast<int>(f * 100.0 + 0.5), seconds);
  std::fflush(stderr);
}

}  // namespace fieldcast::core
