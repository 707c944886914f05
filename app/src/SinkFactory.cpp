#include "SinkFactory.h"

#include "ContactSheet.h"

#include <io_bridge/GpioPulseSink.h>
#include <io_bridge/ImageFileSink.h>
#include <io_bridge/RtpVideoSink.h>
#include <io_bridge/ShmRing.h>
#include <io_bridge/Y4mSink.h>

#include <spdlog/spdlog.h>

#include <filesystem>
#include <stdexcept>

namespace fieldcast::app {
namespace {

// The contact sheet as a sink: thumbnails collected on its own worker, the PNG written at close.
class ContactSheetSink final : public io::FieldSink {
 public:
  ContactSheetSink(std::filesystem::path path, int thumbnails, int keepEveryNth)
      : mPath(std::move(path)), mSheet(thumbnails, 4, 320, keepEveryNth) {}
  std::string name() const override { return "contact_sheet"; }
  void open(const io::StreamFormat&) override {
    if (mPath.has_parent_path()) std::filesystem::create_directories(mPath.parent_path());
  }
  io::SinkStatus consume(const Field& field) override {
    mSheet.add(field);
    return io::SinkStatus::Ok;
  }
  void close() override {
    if (mSheet.candidates() == 0) return;
    mSheet.write(mPath);
    spdlog::info("contact sheet: {}", mPath.string());
  }

 private:
  std::filesystem::path mPath;
  ContactSheet mSheet;
};

void createParent(const std::filesystem::path& path, const char* key) {
  if (path.empty() || path == "-" || !path.has_parent_path()) return;
  std::error_code error;
  std::filesystem::create_directories(path.parent_path(), error);
  if (error) {
    throw std::runtime_error(std::string(key) + ": cannot create folder " + path.parent_path().string() + ": " +
                             error.message());
  }
}

}  // namespace

io::StreamFormat streamFormatOf(const ServiceConfig& config) {
  io::StreamFormat format;
  format.widthPx = config.output.widthPx;
  format.heightPx = config.output.heightPx;
  format.pixelFormat = config.output.format;
  format.scan = config.output.scan;
  format.fieldOrder = config.output.fieldOrder;
  format.fieldRate = config.output.fieldRate;
  format.pixelAspect = io::defaultPixelAspect(format.widthPx, format.heightPx);
  format.validate();
  return format;
}

Sinks makeSinks(const ServiceConfig& config, const io::StreamFormat& format,
                std::function<void(int code, io::WindowKey key)> onKey) {
  Sinks result;
  result.hub = std::make_unique<io::SinkHub>(format, io::SinkHubOptions{8});
  io::SinkHub* hub = result.hub.get();
  const SinksConfig& sinks = config.sinks;
  if (sinks.y4m.enabled) {
    createParent(sinks.y4m.path, "sinks.y4m.path");
    hub->add(std::make_unique<io::Y4mSink>(
        io::Y4mSinkOptions{sinks.y4m.path, sinks.y4m.chroma420 ? io::Y4mChroma::C420 : io::Y4mChroma::C422}));
  }
  if (sinks.rtp.enabled) {
    io::RtpVideoSinkOptions options;
    options.address = sinks.rtp.address;
    options.port = sinks.rtp.port;
    options.mtuBytes = sinks.rtp.mtu;
    hub->add(std::make_unique<io::RtpVideoSink>(options));
  }
  if (sinks.images.enabled) {
    std::error_code error;
    std::filesystem::create_directories(sinks.images.directory, error);
    if (error) {
      throw std::runtime_error("sinks.images.directory: cannot create " + sinks.images.directory.string() + ": " +
                               error.message());
    }
    io::ImageFileSinkOptions options;
    options.directory = sinks.images.directory;
    options.everyNth = sinks.images.everyNth;
    options.format = sinks.images.format == "exr" ? io::ImageFileFormat::Exr : io::ImageFileFormat::Png;
    hub->add(std::make_unique<io::ImageFileSink>(options));
  }
  if (sinks.shm.enabled) hub->add(std::make_unique<io::ShmRingSink>(sinks.shm.name, sinks.shm.slots));
  if (sinks.gpioPulse.enabled) {
    auto line = std::make_unique<io::GpiodPulseLine>(sinks.gpioPulse.chip, static_cast<unsigned>(sinks.gpioPulse.line));
    io::GpioPulseOptions options;
    options.width = fromSeconds(sinks.gpioPulse.widthUs * 1e-6);
    hub->add(std::make_unique<io::GpioPulseSink>(std::move(line), options));
  }
  if (sinks.window.enabled) {
    if (const std::string problem = io::WindowSink::displayProblem(); !problem.empty()) {
      throw std::runtime_error("sinks.window: no live window: " + problem);
    }
    io::WindowSinkOptions options;
    options.onKey = std::move(onKey);
    auto window = std::make_unique<io::WindowSink>(std::move(options));
    result.window = window.get();
    hub->add(std::move(window));
  }
  if (!sinks.contactSheet.empty()) {
    createParent(sinks.contactSheet, "sinks.contact_sheet");
    // One candidate a second; the sheet picks its thumbnails evenly from them at the end.
    const int perSecond = static_cast<int>(config.output.fieldRate.hz() + 0.5);
    hub->add(std::make_unique<ContactSheetSink>(sinks.contactSheet, sinks.contactSheetFields, perSecond));
  }
  return result;
}

}  // namespace fieldcast::app
