#pragma once
// A contact sheet: thumbnails of fields spread evenly through a run, in one PNG a person can
// look at (the demo's picture of what the service emitted). A sink: it collects thumbnails on its
// own SinkHub worker and writes the sheet when the hub closes it.

#include <io_bridge/FieldSink.h>

#include <fieldcast/Field.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace fieldcast::io {

/// What the sheet shows and where it goes.
struct ContactSheetOptions {
  std::filesystem::path path;  ///< the sheet (PNG, or any format OpenImageIO writes by the extension)
  int thumbnails = 12;         ///< pictures on the sheet at most
  int columns = 4;             ///< pictures to a row
  int thumbWidthPx = 320;      ///< width of a picture
  int keepEveryNth = 30;       ///< a candidate every N fields, so a run of unknown length spreads evenly
};

/// Thumbnails kept per picture on the sheet at most: when the candidates reach this many times
/// `thumbnails`, the grid's spacing doubles and those off the new grid are dropped, so a run of any
/// length holds bounded memory and its pictures still spread evenly over it.
inline constexpr int kCandidatesPerThumbnail = 8;

class ContactSheetSink final : public FieldSink {
 public:
  explicit ContactSheetSink(ContactSheetOptions options);

  std::string name() const override { return "contact_sheet"; }
  /// Creates the sheet's folder. Throws std::runtime_error naming it when it cannot.
  void open(const StreamFormat& format) override;
  /// The run's first field (its time is the sheet's zero) and those on the sampling grid.
  bool wants(const Field& field) const noexcept override;
  /// Keeps a thumbnail of `field` when its number falls on the sampling grid (thinning the grid when
  /// the candidates are full). Not RT-safe.
  SinkStatus consume(const Field& field) override;
  /// Writes the sheet when there is anything on it.
  void close() override;

  /// Writes the sheet now, each thumbnail labelled with its field number and the time from the
  /// first field. Throws std::runtime_error naming the path on failure or when there is nothing.
  void write() const;
  std::size_t candidates() const noexcept { return mCandidates.size(); }
  /// The sampling grid's spacing now: keepEveryNth, doubled each time the candidates filled.
  std::uint64_t everyNth() const noexcept { return mEveryNth.load(std::memory_order_relaxed); }

 private:
  struct Thumbnail {
    std::vector<unsigned char> rgb;  ///< thumbWidth × height × 3
    int heightPx = 0;
    std::uint64_t fieldNumber = 0;
    double secondsFromStart = 0.0;
  };
  bool onGrid(const Field& field) const noexcept;  // its number a multiple of everyNth()

  ContactSheetOptions mOptions;
  TimePoint mFirstDisplayTime{};
  std::atomic<bool> mHaveFirst{false};   // written by consume(), read by wants() on the field thread
  std::atomic<std::uint64_t> mEveryNth;  // likewise
  std::vector<std::uint8_t> mRgb;        // the field being thumbnailed, as RGB
  std::vector<Thumbnail> mCandidates;
};

}  // namespace fieldcast::io
