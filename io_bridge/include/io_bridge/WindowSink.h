#pragma once
// A live window (OpenCV highgui) showing the output at its rate, with the figures that matter
// overlaid (render rate, fields, missed fields, margin violations) and the keys pressed in it
// handed to a callback, so a keyboard can fly when no stick is present. Interlaced fields are
// woven into the rows of their parity, as an interlaced monitor would show them.

#include <io_bridge/FieldSink.h>

#include <fieldcast/SeqLock.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace fieldcast::io {

/// The figures the overlay shows; published by the service from any thread.
struct WindowFigures {
  double renderHz = 0.0;           ///< frames rendered per second (recent)
  std::uint64_t fields = 0;        ///< fields emitted
  std::uint64_t missedFields = 0;  ///< fields the field thread could not make in time
  /// Output pixels sampled outside the frame (outside its footprint, for a rolled one), total
  std::uint64_t marginViolations = 0;
};

/// Keys a keyboard flight needs, decoded from highgui's key codes (Qt and GTK backends).
enum class WindowKey : std::uint8_t {
  Other,
  Left,
  Right,
  Up,
  Down,  ///< arrows (also A, D, W, S)
  Faster,
  Slower,    ///< + / − (also = and _)
  Reset,     ///< R
  Snapshot,  ///< space
  Quit,      ///< Esc or Q
};
/// Decodes a waitKeyEx() code. RT-safe.
WindowKey decodeWindowKey(int code) noexcept;

struct WindowSinkOptions {
  std::string title = "Fieldcast";
  bool overlay = true;
  /// Called on the window's thread for every key pressed in the window, with the raw code and
  /// its decoding. Keep it short (store into an atomic or a SeqLock).
  std::function<void(int code, WindowKey key)> onKey;
};

/// The window. Not RT-safe (GUI): runs on its SinkHub worker, which owns the window. highgui
/// (Qt) belongs to the first thread that uses it, so a process has one window thread: open()
/// from another thread throws instead of deadlocking.
class WindowSink final : public FieldSink {
 public:
  explicit WindowSink(WindowSinkOptions options);
  ~WindowSink() override;

  std::string name() const override { return "window"; }
  /// Opens the window; throws std::runtime_error with a clear message when there is no display
  /// (instead of letting the GUI toolkit abort the process).
  void open(const StreamFormat& format) override;
  SinkStatus consume(const Field& field) override;
  void close() override;
  std::string endReason() const override { return mEndReason; }

  /// Publishes the figures the overlay shows. Any thread, RT-safe.
  void setFigures(const WindowFigures& figures) noexcept { mFigures.store(figures); }
  /// Fields shown so far.
  std::uint64_t fieldsShown() const noexcept { return mShown; }

  /// Why no window can be opened here ("DISPLAY is not set", "cannot connect to X display :1"),
  /// or empty when an X display answers. Checks the X server's socket, so it never aborts.
  static std::string displayProblem();

 private:
  struct State;
  WindowSinkOptions mOptions;
  std::unique_ptr<State> mState;
  SeqLock<WindowFigures> mFigures;
  std::uint64_t mShown = 0;
  std::string mEndReason;
};

}  // namespace fieldcast::io
