#pragma once
// A field-sync pulse on a GPIO line: high at each field's display time t_k for a configured
// width, so a scope, a camera trigger or another channel's genlock can see exactly when each
// field is due. The line is behind a small interface: libgpiod v1 on real hardware, a recording
// fake in tests.

#include <io_bridge/FieldSink.h>

#include <fieldcast/Time.h>

#include <cstdint>
#include <memory>
#include <string>

namespace fieldcast::io {

/// A digital output line.
class PulseLine {
 public:
  virtual ~PulseLine() = default;
  /// Drives the line high (true) or low. RT-safe in both implementations (one ioctl).
  virtual void set(bool high) noexcept = 0;
  /// "gpiochip0 line 17", for logs.
  virtual std::string describe() const = 0;
};

/// A line of a GPIO chip through libgpiod v1 (the character device, /dev/gpiochipN), requested
/// as an output, initially low, under the consumer name "fieldcast".
class GpiodPulseLine final : public PulseLine {
 public:
  /// `chip` is a name ("gpiochip0"), a path ("/dev/gpiochip0"), a label or a number. Throws
  /// std::runtime_error naming the chip and line when it cannot be opened or requested.
  GpiodPulseLine(const std::string& chip, unsigned lineOffset);
  ~GpiodPulseLine() override;
  void set(bool high) noexcept override;
  std::string describe() const override;

 private:
  struct Handles;
  std::unique_ptr<Handles> mHandles;
  std::string mChip;
  unsigned mOffset;
};

struct GpioPulseOptions {
  Nanoseconds width = std::chrono::microseconds(500);  ///< how long the line stays high
  /// A field whose display time passed more than this long ago gets no pulse (a late edge would
  /// lie about the field's timing); it is counted instead.
  Nanoseconds lateTolerance = std::chrono::microseconds(200);
};

/// Pulses the line for every field. Sleeps to absolute deadlines on the given clock; runs on a
/// SinkHub worker (give that thread real-time priority for tight edges).
class GpioPulseSink final : public FieldSink {
 public:
  GpioPulseSink(std::unique_ptr<PulseLine> line, GpioPulseOptions options, std::shared_ptr<Clock> clock = nullptr);
  std::string name() const override { return "gpio_pulse"; }
  void open(const StreamFormat& format) override;
  SinkStatus consume(const Field& field) override;
  void close() override;

  std::uint64_t pulses() const noexcept { return mPulses; }
  std::uint64_t latePulses() const noexcept { return mLate; }

 private:
  std::unique_ptr<PulseLine> mLine;
  GpioPulseOptions mOptions;
  std::shared_ptr<Clock> mClock;
  std::uint64_t mPulses = 0;
  std::uint64_t mLate = 0;
};

}  // namespace fieldcast::io
