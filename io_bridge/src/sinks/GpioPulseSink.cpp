// Field pulse: rising edge at t_k, falling edge at t_k + width, both by clock_nanosleep to
// absolute deadlines (the Clock interface), never relative sleeps.

#include <io_bridge/GpioPulseSink.h>

#include <gpiod.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace fieldcast::io {

struct GpiodPulseLine::Handles {
  gpiod_chip* chip = nullptr;
  gpiod_line* line = nullptr;
};

GpiodPulseLine::GpiodPulseLine(const std::string& chip, unsigned lineOffset)
    : mHandles(std::make_unique<Handles>()), mChip(chip), mOffset(lineOffset) {
  mHandles->chip = gpiod_chip_open_lookup(chip.c_str());
  if (!mHandles->chip) {
    throw std::runtime_error("sinks.gpio_pulse: cannot open GPIO chip '" + chip + "': " + std::strerror(errno));
  }
  mHandles->line = gpiod_chip_get_line(mHandles->chip, lineOffset);
  if (!mHandles->line || gpiod_line_request_output(mHandles->line, "fieldcast", 0) != 0) {
    const int e = errno;
    gpiod_chip_close(mHandles->chip);
    throw std::runtime_error("sinks.gpio_pulse: cannot request " + describe() + " as an output: " + std::strerror(e));
  }
}

GpiodPulseLine::~GpiodPulseLine() {
  if (mHandles->line) {
    gpiod_line_set_value(mHandles->line, 0);
    gpiod_line_release(mHandles->line);
  }
  if (mHandles->chip) gpiod_chip_close(mHandles->chip);
}

void GpiodPulseLine::set(bool high) noexcept { gpiod_line_set_value(mHandles->line, high ? 1 : 0); }

std::string GpiodPulseLine::describe() const { return mChip + " line " + std::to_string(mOffset); }

GpioPulseSink::GpioPulseSink(std::unique_ptr<PulseLine> line, GpioPulseOptions options, std::shared_ptr<Clock> clock)
    : mLine(std::move(line)), mOptions(options), mClock(clock ? std::move(clock) : std::make_shared<SystemClock>()) {
  if (!mLine) throw std::invalid_argument("GpioPulseSink: no line");
  if (mOptions.width <= Nanoseconds::zero()) throw std::invalid_argument("sinks.gpio_pulse.width_us must be positive");
}

void GpioPulseSink::open(const StreamFormat& format) {
  if (mOptions.width >= format.fieldRate.period()) {
    throw std::invalid_argument("sinks.gpio_pulse: width " + std::to_string(mOptions.width.count() / 1000) +
                                " us is not shorter than a field period");
  }
  mLine->set(false);
}

SinkStatus GpioPulseSink::consume(const Field& field) {
  mClock->sleepUntil(field.displayTime);
  if (mClock->now() - field.displayTime > mOptions.lateTolerance) {
    ++mLate;
    return SinkStatus::Ok;
  }
  mLine->set(true);
  mClock->sleepUntil(field.displayTime + mOptions.width);
  mLine->set(false);
  ++mPulses;
  return SinkStatus::Ok;
}

void GpioPulseSink::close() { mLine->set(false); }

}  // namespace fieldcast::io
