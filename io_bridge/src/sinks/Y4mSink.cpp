// YUV4MPEG2 as specified by the mjpegtools yuv4mpeg(5) manual page: one header line, then per
// frame "FRAME\n" and the Y, Cb, Cr planes. Fields of an interlaced stream are woven into the
// rows of their parity; a frame is written once both of its fields are in, or when a field of a
// later frame shows the partner was lost.

#include <io_bridge/Y4mSink.h>

#include "FileOutput.h"
#include "PixelConvert.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace fieldcast::io {

struct Y4mSink::State {
  StreamFormat format;
  FileOutput out;
  int chromaWidth = 0;
  int chromaHeight = 0;                    // rows of the output chroma planes
  std::vector<std::uint8_t> lumaPlane;     // full frame, frame row order
  std::vector<std::uint8_t> cb422, cr422;  // 4:2:2 chroma of the full frame, frame row order
  std::vector<std::uint8_t> cbOut, crOut;  // 4:2:0 planes (unused for 4:2:2)
  std::vector<std::uint8_t> uyvyRow;
  std::int64_t pendingFrame = -1;         // frame index whose fields are being collected
  int pendingFields = 0;                  // bit 0: first field in, bit 1: second field in
  std::int64_t pendingFrameWritten = -1;  // index of the frame the stored rows belong to
  std::int64_t nextFrame = 0;             // index of the next frame the file needs
  std::int64_t firstScheduledFrame = -1;  // the schedule's first frame (scheduleStarted), if told
  bool consumedAny = false;
  std::int64_t leadingFrames = 0;  // frames of the schedule before the first field's, never made
  std::uint64_t repeated = 0;      // frames repeated to fill missed ones
  std::uint64_t frames = 0;
  std::uint64_t incomplete = 0;
  std::string endReason;

  void storeRows(const Field& field);
  bool writeFrame();
  bool repeatLastFrameUntil(std::int64_t frame);
};

// A Y4M file has no timestamps: frames the field thread missed entirely are filled by repeating
// the last picture, so the video keeps time with the schedule. False when the write failed.
bool Y4mSink::State::repeatLastFrameUntil(std::int64_t frame) {
  while (frames > 0 && nextFrame < frame) {
    pendingFields = 3;
    if (!writeFrame()) return false;
    ++repeated;
    ++nextFrame;
  }
  return true;
}

Y4mSink::Y4mSink(Y4mSinkOptions options) : mOptions(std::move(options)) {}
Y4mSink::~Y4mSink() = default;

std::string Y4mSink::header(const StreamFormat& format, Y4mChroma chroma) {
  const RationalRate rate = format.frameRate();
  std::ostringstream s;
  s << "YUV4MPEG2 W" << format.widthPx << " H" << format.heightPx << " F" << rate.numerator << ':' << rate.denominator
    << ' ' << (format.scan == ScanMode::Progressive ? "Ip" : (format.fieldOrder == FieldOrder::TopFirst ? "It" : "Ib"))
    << " A" << format.pixelAspect.numerator << ':' << format.pixelAspect.denominator << ' '
    << (chroma == Y4mChroma::C420 ? "C420mpeg2" : "C422") << " XCOLORRANGE=LIMITED\n";
  return s.str();
}

void Y4mSink::open(const StreamFormat& format) {
  format.validate();
  auto st = std::make_unique<State>();
  st->format = format;
  st->chromaWidth = (format.widthPx + 1) / 2;
  st->chromaHeight = mOptions.chroma == Y4mChroma::C420 ? (format.heightPx + 1) / 2 : format.heightPx;
  const auto w = static_cast<std::size_t>(format.widthPx), h = static_cast<std::size_t>(format.heightPx);
  const auto cw = static_cast<std::size_t>(st->chromaWidth);
  st->lumaPlane.assign(w * h, 16);
  st->cb422.assign(cw * h, 128);
  st->cr422.assign(cw * h, 128);
  if (mOptions.chroma == Y4mChroma::C420) {
    st->cbOut.assign(cw * static_cast<std::size_t>(st->chromaHeight), 128);
    st->crOut.assign(cw * static_cast<std::size_t>(st->chromaHeight), 128);
  }
  st->uyvyRow.assign(cw * 4, 0);
  st->out.open(mOptions.path);
  const std::string head = header(format, mOptions.chroma);
  if (!st->out.writeAll(head.data(), head.size())) throw std::runtime_error(st->out.error());
  mState = std::move(st);
}

void Y4mSink::State::storeRows(const Field& field) {
  const int w = format.widthPx;
  for (int r = 0; r < field.image.heightPx(); ++r) {
    const auto row = static_cast<std::size_t>(rasterRow(field.parity, r));
    rowToUyvy(field.image.row(r), field.image.format(), w, uyvyRow.data());
    uyvyToPlanar(uyvyRow.data(), w, lumaPlane.data() + row * static_cast<std::size_t>(w),
                 cb422.data() + row * static_cast<std::size_t>(chromaWidth),
                 cr422.data() + row * static_cast<std::size_t>(chromaWidth));
  }
}

bool Y4mSink::State::writeFrame() {
  const auto cw = static_cast<std::size_t>(chromaWidth);
  const int h = format.heightPx;
  const std::uint8_t* cb = cb422.data();
  const std::uint8_t* cr = cr422.data();
  if (!cbOut.empty()) {
    // 4:2:0: average pairs of lines of the same field (MPEG-2 interlaced 4:2:0 interleaves the
    // chroma lines of the two fields); progressive frames average adjacent lines.
    const bool interlaced = format.scan == ScanMode::Interlaced;
    for (int c = 0; c < chromaHeight; ++c) {
      int a, b;
      if (interlaced) {
        const FieldParity parity = (c % 2 == 0) ? FieldParity::Top : FieldParity::Bottom;
        const int rows = fieldRowCount(parity, h);
        const int first = std::min(2 * (c / 2), rows - 1);
        a = rasterRow(parity, first);
        b = rasterRow(parity, std::min(first + 1, rows - 1));
      } else {
        a = 2 * c;
        b = std::min(2 * c + 1, h - 1);
      }
      const std::size_t ra = static_cast<std::size_t>(a) * cw, rb = static_cast<std::size_t>(b) * cw;
      const std::size_t ro = static_cast<std::size_t>(c) * cw;
      averageRows(cb422.data() + ra, cb422.data() + rb, chromaWidth, cbOut.data() + ro);
      averageRows(cr422.data() + ra, cr422.data() + rb, chromaWidth, crOut.data() + ro);
    }
    cb = cbOut.data();
    cr = crOut.data();
  }
  static constexpr char kFrame[] = "FRAME\n";
  const std::size_t chromaBytes = cw * static_cast<std::size_t>(chromaHeight);
  iovec parts[4] = {{const_cast<char*>(kFrame), sizeof(kFrame) - 1},
                    {lumaPlane.data(), lumaPlane.size()},
                    {const_cast<std::uint8_t*>(cb), chromaBytes},
                    {const_cast<std::uint8_t*>(cr), chromaBytes}};
  // The first picture also stands for the frames of the schedule before it, whose fields never
  // came (a stall at the run's start), so the file keeps time from the schedule's first frame.
  const std::int64_t copies = frames == 0 ? 1 + leadingFrames : 1;
  for (std::int64_t k = 0; k < copies; ++k) {
    if (!out.writeAll(parts, 4)) {
      endReason = out.error();
      return false;
    }
    ++frames;
  }
  repeated += static_cast<std::uint64_t>(copies - 1);
  if (format.scan == ScanMode::Interlaced && pendingFields != 3) ++incomplete;
  pendingFields = 0;
  pendingFrame = -1;
  return true;
}

SinkStatus Y4mSink::consume(const Field& field) {
  State& st = *mState;
  const bool progressive = st.format.scan == ScanMode::Progressive;
  // Field k belongs to frame k / 2 (interlaced; the first field of each frame has the even number).
  const auto frame = static_cast<std::int64_t>(progressive ? field.fieldNumber : field.fieldNumber / 2);
  if (!st.consumedAny) {
    // Counted now, in the numbering the schedule started in (a later move onto another lock
    // renumbers the fields; a first field already renumbered counts in another one: no fill)
    st.consumedAny = true;
    if (st.firstScheduledFrame >= 0 && !field.renumbered)
      st.leadingFrames = std::max<std::int64_t>(0, frame - st.firstScheduledFrame);
  }
  if (field.renumbered) {
    // The field clock moved onto another frame lock: the numbers jump, the pictures go on. A frame
    // half made takes this field as its partner under the new number; nothing is repeated.
    if (st.pendingFrame >= 0) st.pendingFrame = st.pendingFrameWritten = frame;
    st.nextFrame = frame;
  }
  if (st.pendingFrame >= 0 && frame != st.pendingFrame) {
    if (!st.writeFrame()) return SinkStatus::Ended;  // its partner field never came
    st.nextFrame = st.pendingFrameWritten + 1;
  }
  if (!st.repeatLastFrameUntil(frame)) return SinkStatus::Ended;
  st.pendingFrame = frame;
  st.storeRows(field);
  st.pendingFields |= progressive ? 3 : (field.fieldNumber % 2 == 0) ? 1 : 2;
  if (st.pendingFields == 3) {
    st.pendingFrameWritten = frame;
    if (!st.writeFrame()) return SinkStatus::Ended;
    st.nextFrame = frame + 1;
  } else {
    st.pendingFrameWritten = frame;
  }
  return SinkStatus::Ok;
}

void Y4mSink::scheduleStarted(std::uint64_t firstField) {
  if (!mState) return;
  const bool progressive = mState->format.scan == ScanMode::Progressive;
  mState->firstScheduledFrame = static_cast<std::int64_t>(progressive ? firstField : firstField / 2);
}

void Y4mSink::scheduleEnded(std::uint64_t firstFieldAfter) {
  if (!mState || !mState->endReason.empty()) return;
  State& st = *mState;
  const bool progressive = st.format.scan == ScanMode::Progressive;
  // Frames the schedule reached: field k belongs to frame k / 2 (interlaced).
  const auto endFrame = static_cast<std::int64_t>(progressive ? firstFieldAfter : (firstFieldAfter + 1) / 2);
  if (st.pendingFrame >= 0) {
    if (!st.writeFrame()) return;  // its partner field never came
    st.nextFrame = st.pendingFrameWritten + 1;
  }
  st.repeatLastFrameUntil(endFrame);
}

void Y4mSink::close() {
  if (!mState) return;
  if (mState->pendingFrame >= 0 && mState->endReason.empty()) mState->writeFrame();
  mState->out.close();
}

std::string Y4mSink::endReason() const { return mState ? mState->endReason : std::string{}; }
std::uint64_t Y4mSink::framesWritten() const noexcept { return mState ? mState->frames : 0; }
std::uint64_t Y4mSink::framesRepeated() const noexcept { return mState ? mState->repeated : 0; }
std::uint64_t Y4mSink::incompleteFrames() const noexcept { return mState ? mState->incomplete : 0; }

}  // namespace fieldcast::io
