#pragma once
// A contact sheet: thumbnails of fields spread evenly through a run, in one PNG a person can
// look at (the demo's picture of what the service emitted). Fed off the field thread.

#include <fieldcast/Field.h>

#include <filesystem>
#include <string>
#include <vector>

namespace fieldcast::app {

class ContactSheet {
 public:
  /// `thumbnails` pictures of `thumbWidthPx` columns, `columns` to a row; a candidate is kept
  /// every `keepEveryNth` fields so a run of unknown length still spreads evenly.
  ContactSheet(int thumbnails = 12, int columns = 4, int thumbWidthPx = 320, int keepEveryNth = 30);

  /// Keeps a thumbnail of `field` when its number falls on the sampling grid. Not RT-safe.
  void add(const Field& field);
  /// Writes the sheet (PNG, by the extension) with each thumbnail labelled with its field
  /// number and time from the first field. Throws std::runtime_error naming the path on failure.
  void write(const std::filesystem::path& path) const;
  std::size_t candidates() const noexcept { return mCandidates.size(); }

 private:
  struct Thumbnail {
    std::vector<unsigned char> rgb;  ///< thumbWidth × height × 3
    int heightPx = 0;
    std::uint64_t fieldNumber = 0;
    double secondsFromStart = 0.0;
  };
  int mThumbnails;
  int mColumns;
  int mThumbWidthPx;
  int mKeepEveryNth;
  TimePoint mFirstDisplayTime{};
  bool mHaveFirst = false;
  std::vector<Thumbnail> mCandidates;
};

}  // namespace fieldcast::app
