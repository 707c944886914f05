#pragma once
// The fieldcast service: the three stages of DESIGN.md §1 wired from a ServiceConfig. The
// terrain is opened (the built-in one built on first use), the render thread renders frames for
// predicted poses, the field thread warps the newest frame to every field's display time and
// hands the field to the sinks, and an input thread feeds the stick flight model.

#include <service/ServiceConfig.h>
#include <service/ServiceMetrics.h>

#include <atomic>
#include <memory>
#include <string>

namespace fieldcast::app {

class Service {
 public:
  /// Opens the terrain, the motion source, the input and the outputs. Throws std::runtime_error
  /// (or ConfigError) with a message naming what could not be opened and why.
  explicit Service(const ServiceConfig& config);
  ~Service();
  Service(const Service&) = delete;
  Service& operator=(const Service&) = delete;

  /// Locks memory where allowed, opens the outputs, starts the render thread and waits for its
  /// first frame, then starts the field thread, which warms up (one warp of that frame) before the
  /// field clock and its first deadline exist. Throws on failure.
  void start();
  /// False once a thread has hit a fatal error (see fatalError()) or the run's duration is over.
  bool running() const noexcept;
  /// The reason a thread stopped the service; empty when none did.
  std::string fatalError() const;
  /// The log line for the last interval (call about once a second from one thread).
  std::string intervalLine();
  /// Stops the threads, finalises every output (a Y4M file is complete), writes the JSON summary
  /// and returns the run's figures. Idempotent.
  ServiceFigures stop();

 private:
  struct Parts;
  std::unique_ptr<Parts> mParts;
};

}  // namespace fieldcast::app
