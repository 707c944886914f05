#pragma once
// Fields as image files through OpenImageIO: every Nth field and on demand, as 8-bit PNG (to
// look at) or half-float OpenEXR (to analyse: linear light, and for frames the per-pixel range
// as a Z channel). A field of an interlaced stream is written as the rows it carries, with a
// pixel aspect ratio of half the raster's so viewers that honour it show it undistorted.

#include <io_bridge/FieldSink.h>

#include <fieldcast/Frame.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace fieldcast::io {

enum class ImageFileFormat : std::uint8_t {
  Png,  ///< 8-bit sRGB RGB
  Exr,  ///< half-float linear RGB (plus Z for frames with a range image)
};

struct ImageFileSinkOptions {
  std::filesystem::path directory;  ///< must exist
  int everyNth = 60;                ///< write fields whose number is a multiple of N; 0: only on demand
  ImageFileFormat format = ImageFileFormat::Png;
  std::string prefix = "field";  ///< file names: <prefix>_<field number, 8 digits>_<parity>.<ext>
};

/// Writes selected fields to files. Not RT-safe (encoding, file I/O): runs on a SinkHub worker.
class ImageFileSink final : public FieldSink {
 public:
  explicit ImageFileSink(ImageFileSinkOptions options);
  ~ImageFileSink() override;

  std::string name() const override { return "images"; }
  void open(const StreamFormat& format) override;
  /// Only the fields it writes: every Nth, and after requestSnapshot() every field until one is
  /// written (the worker may still be on an earlier one).
  bool wants(const Field& field) const noexcept override;
  SinkStatus consume(const Field& field) override;
  void close() override;

  /// Asks for the next field to be written whatever its number. Any thread, RT-safe.
  void requestSnapshot() noexcept { mSnapshot.store(true, std::memory_order_relaxed); }
  /// Files written so far (read on the worker or after close()).
  std::uint64_t filesWritten() const noexcept { return mWritten; }
  /// Path of the last file written.
  const std::filesystem::path& lastPath() const noexcept { return mLastPath; }

  /// File name of field k in this sink's scheme, e.g. "field_00000120_bottom.png".
  std::string fileName(const Field& field) const;

 private:
  bool due(const Field& field) const noexcept;  // its number a multiple of everyNth

  ImageFileSinkOptions mOptions;
  StreamFormat mFormat;
  std::vector<std::uint8_t> mRgb;
  std::vector<float> mLinear;
  std::atomic<bool> mSnapshot{false};
  std::uint64_t mWritten = 0;
  std::filesystem::path mLastPath;
  std::string mEndReason;

 public:
  std::string endReason() const override { return mEndReason; }
};

/// Writes a rendered frame (margins included) for analysis: EXR with linear half-float RGB and,
/// when the frame has a range image, a float Z channel in metres (+inf for sky); PNG with RGB
/// only. Metadata: frame number, pose time, margin. Throws std::runtime_error naming the file.
void writeFrameImage(const Frame& frame, const std::filesystem::path& path);

}  // namespace fieldcast::io
