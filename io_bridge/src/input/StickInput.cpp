#include <io_bridge/StickInput.h>

#include <spdlog/spdlog.h>

#include <algorithm>

namespace fieldcast::io {

ControlState decayToward(const ControlState& held, TimePoint t, const StickProfile& profile) noexcept {
  if (held.health != InputHealth::Holding) return held;
  ControlState s = held;
  const double elapsedS = toSeconds(t - held.lostAt);
  const double keep = profile.lossDecayS <= 0.0 ? 0.0 : std::clamp(1.0 - elapsedS / profile.lossDecayS, 0.0, 1.0);
  s.roll *= keep;
  s.pitch *= keep;
  s.yaw *= keep;
  if (profile.throttleOnLoss == ThrottleOnLoss::Neutral) {
    s.throttle = profile.defaultThrottle + (held.throttle - profile.defaultThrottle) * keep;
  }
  s.buttons = 0;  // a held trigger must not keep firing
  s.hat = kHatCentred;
  return s;
}

StickInput::StickInput(SourceFactory factory, StickProfile profile, StickInputOptions options, Clock& clock)
    : mFactory(std::move(factory)),
      mProfile(std::move(profile)),
      mOptions(std::move(options)),
      mClock(clock),
      mBackoff(mOptions.backoffMin, mOptions.backoffMax) {
  mHeld.throttle = mProfile.defaultThrottle;
  mPublished.store(mHeld);
  mNextAttempt = mClock.now();
}

StickInput::~StickInput() { stop(); }

void StickInput::start() {
  if (mRunning.exchange(true)) return;
  mThread = std::thread([this] {
    try {
      while (mRunning.load(std::memory_order_relaxed) && step()) {
      }
    } catch (const std::exception& e) {
      spdlog::error("stick input thread stopped: {}", e.what());
    }
  });
}

void StickInput::stop() {
  mRunning.store(false);
  if (mThread.joinable()) mThread.join();
  if (mRecorder) mRecorder->flush();
}

StickInputStats StickInput::stats() const noexcept {
  return StickInputStats{mFrames.load(),   mConnects.load(), mLosses.load(),  mFailedOpens.load(),
                         mRejected.load(), mDropped.load(),  mArrivals.load()};
}

void StickInput::lose(TimePoint now, const char* why) {
  const std::string name = mSource ? mSource->description().name : std::string("stick");
  mRejectedBefore = mRejected.load();
  mDroppedBefore = mDropped.load();
  mSource.reset();
  mMapper.reset();
  mHeld.health = InputHealth::Holding;
  mHeld.lostAt = now;
  mPublished.store(mHeld);
  ++mLosses;
  if (mRecorder) {
    const InputEvent lost{now.time_since_epoch().count(), 0, 0, InputEventType::DeviceLost};
    mRecorder->write(std::span<const InputEvent>(&lost, 1));
    mRecorder->flush();
  }
  if (!mOptions.reconnect) {
    mFinished = true;
    spdlog::info("stick \"{}\" {}: holding the last state, decaying to neutral over {} s", name, why,
                 mProfile.lossDecayS);
    return;
  }
  // Logged once per loss; the reconnection attempts that follow are silent until one succeeds.
  spdlog::warn("stick \"{}\" {}: holding the last state, decaying to neutral over {} s; reconnecting", name, why,
               mProfile.lossDecayS);
  mFailureLogged = true;
  mBackoff.reset();
  mNextAttempt = now + mBackoff.next();
}

bool StickInput::step() {
  if (mFinished) return false;
  const TimePoint now = mClock.now();
  if (!mSource) {
    if (now < mNextAttempt) {
      const Nanoseconds wait = std::min(mNextAttempt - now, mOptions.readTimeout);
      if (mOptions.arrivals && mOptions.arrivals->waitForArrival(wait)) {
        ++mArrivals;
        mNextAttempt = mClock.now();  // the device may be back: try now, not at the next poll
        return true;
      }
      // No arrival (or no hotplug): the backoff poll. After a watch that waited, this returns at once.
      mClock.sleepUntil(std::min(mNextAttempt, now + mOptions.readTimeout));
      return true;
    }
    try {
      mSource = mFactory();
    } catch (const std::exception& e) {
      ++mFailedOpens;
      if (!mFailureLogged) spdlog::warn("stick not available ({}); retrying with backoff", e.what());
      mFailureLogged = true;
      mNextAttempt = now + mBackoff.next();
      return true;
    }
    mMapper.emplace(mSource->description(), mProfile);
    mBackoff.reset();
    mFailureLogged = false;
    ++mConnects;
    spdlog::info("stick connected: {}", mMapper->describeBindings());
    if (!mOptions.recordPath.empty()) {
      if (!mRecorder) mRecorder = std::make_unique<InputRecorder>(mOptions.recordPath, mSource->description());
      if (mConnects > 1) {
        const InputEvent found{now.time_since_epoch().count(), 0, 0, InputEventType::DeviceFound};
        mRecorder->write(std::span<const InputEvent>(&found, 1));
      }
    }
    return true;
  }
  mEvents.clear();
  ReadResult r = ReadResult::Timeout;
  try {
    r = mSource->read(mEvents, mOptions.readTimeout);
  } catch (const std::exception& e) {
    spdlog::warn("stick read failed: {}", e.what());
    r = ReadResult::Lost;
  }
  const InputSourceStats sourceStats = mSource->stats();
  mRejected.store(mRejectedBefore + sourceStats.rejectedReports);
  mDropped.store(mDroppedBefore + sourceStats.droppedBursts);
  if (mRecorder && !mEvents.empty()) mRecorder->write(mEvents);
  for (const InputEvent& e : mEvents) {
    if (mMapper->apply(e)) {
      mHeld = mMapper->state();
      mPublished.store(mHeld);
      ++mFrames;
    }
  }
  if (r == ReadResult::Lost) lose(mClock.now(), "lost");
  if (r == ReadResult::End) lose(mClock.now(), "ended");
  return !mFinished;
}

}  // namespace fieldcast::io
