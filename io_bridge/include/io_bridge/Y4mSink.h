#pragma once
// YUV4MPEG2 (.y4m) output to a file or to standard output: the format ffmpeg, mpv, x264 and
// most analysis tools read without being told anything. Interlaced streams are written as
// frames of two woven fields with the field order in the header (It / Ib).

#include <io_bridge/FieldSink.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace fieldcast::io {

/// Chroma sampling of the Y4M planes.
enum class Y4mChroma : std::uint8_t {
  C420,  ///< 4:2:0, chroma co-sited horizontally, between lines vertically ("C420mpeg2");
         ///< interlaced frames subsample each field on its own (MPEG-2 interlaced 4:2:0)
  C422,  ///< 4:2:2, the sampling of the fields themselves: lossless for UYVY fields
};

struct Y4mSinkOptions {
  std::filesystem::path path;  ///< file to write, or "-" for standard output
  Y4mChroma chroma = Y4mChroma::C420;
};

/// Writes every field to a Y4M stream. Not RT-safe (file I/O): runs on a SinkHub worker.
class Y4mSink final : public FieldSink {
 public:
  explicit Y4mSink(Y4mSinkOptions options);
  ~Y4mSink() override;

  std::string name() const override { return "y4m"; }
  void open(const StreamFormat& format) override;
  SinkStatus consume(const Field& field) override;
  /// Frames of the schedule whose fields never came at its start or its end are filled too (with
  /// the first picture, with the last), so a run of N seconds is N seconds of video whatever it
  /// missed.
  void scheduleStarted(std::uint64_t firstField) override;
  void scheduleEnded(std::uint64_t firstFieldAfter) override;
  void close() override;
  std::string endReason() const override;

  /// The stream header line for `format` (with its newline), e.g.
  /// "YUV4MPEG2 W720 H486 F30000:1001 Ib A10:11 C420mpeg2 XCOLORRANGE=LIMITED\n".
  static std::string header(const StreamFormat& format, Y4mChroma chroma);
  /// Frames written so far, and frames written with one field missing (its rows keep the
  /// previous field of that parity).
  std::uint64_t framesWritten() const noexcept;
  /// Frames written again in place of frames whose fields never came (missed by the field thread).
  std::uint64_t framesRepeated() const noexcept;
  std::uint64_t incompleteFrames() const noexcept;

 private:
  struct State;
  Y4mSinkOptions mOptions;
  std::unique_ptr<State> mState;
};

}  // namespace fieldcast::io
