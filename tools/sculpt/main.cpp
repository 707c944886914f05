// fieldcast-sculpt: a voxel model from three photographs of an object (side, front, top), written
// as a MagicaVoxel .vox file a placement list can name (ig_core/README.md, "Sculpted models").
//
//   fieldcast-sculpt --side side.png --front front.png --top top.png --height 2.4 -o van.vox
//                    [--key 00ff00 [--key-tolerance 24]] [--preview views.png]
#include <ig_core/Sculpt.h>
#include <ig_core/VoxFile.h>
#include <tools/OptionChecks.h>

#include <OpenImageIO/imageio.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace {

using namespace fieldcast::core;

// "#rrggbb" or "rrggbb" as RGB8 with R in the low byte
CLI::Validator hexColour() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const std::string hex = !text.empty() && text[0] == '#' ? text.substr(1) : text;
        if (hex.size() != 6 || hex.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos) {
          return "expected a colour as rrggbb (hexadecimal, like 00ff00), got '" + text + "'";
        }
        return {};
      },
      "RRGGBB");
}

std::uint32_t parseHex(const std::string& text) {
  const unsigned long v = std::stoul(!text.empty() && text[0] == '#' ? text.substr(1) : text, nullptr, 16);
  return static_cast<std::uint32_t>(((v >> 16) & 0xFF) | (v & 0xFF00) | ((v & 0xFF) << 16)) | 0xFF000000u;
}

// The solid's side, front and top views (Sculpt.h's conventions) side by side, 8 px a voxel on
// grey: to set beside the photographs
void writePreview(const std::string& path, const VoxelSolid& s) {
  constexpr int kPx = 8, kGap = 16;
  const int widths[3] = {s.sizeY, s.sizeX, s.sizeX}, heights[3] = {s.sizeZ, s.sizeZ, s.sizeY};
  const int w = kPx * (widths[0] + widths[1] + widths[2]) + 4 * kGap;
  const int h = kPx * std::max(s.sizeZ, s.sizeY) + 2 * kGap;
  std::vector<unsigned char> rgb(static_cast<std::size_t>(w * h * 3), 96);
  int left = kGap;
  for (int view = 0; view < 3; ++view) {
    for (int b = 0; b < heights[view]; ++b)
      for (int a = 0; a < widths[view]; ++a) {
        const int depth = view == 0 ? s.sizeX : view == 1 ? s.sizeY : s.sizeZ;
        for (int d = depth - 1; d >= 0; --d) {
          const int x = view == 0 ? d : view == 1 ? s.sizeX - 1 - a : a;
          const int y = view == 0 ? a : view == 1 ? d : s.sizeY - 1 - b;
          const int z = view == 2 ? d : s.sizeZ - 1 - b;
          if (!s.filled(x, y, z)) continue;
          const std::uint32_t c = s.rgba[s.index(x, y, z)];
          for (int py = 0; py < kPx; ++py)
            for (int px = 0; px < kPx; ++px) {
              const std::size_t at = (static_cast<std::size_t>(kGap + b * kPx + py) * static_cast<std::size_t>(w) +
                                      static_cast<std::size_t>(left + a * kPx + px)) *
                                     3;
              for (int k = 0; k < 3; ++k)
                rgb[at + static_cast<std::size_t>(k)] = static_cast<unsigned char>(c >> (8 * k));
            }
          break;
        }
      }
    left += widths[view] * kPx + kGap;
  }
  auto out = OIIO::ImageOutput::create(path);
  if (!out || !out->open(path, OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8)) ||
      !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) || !out->close()) {
    throw std::runtime_error(path + ": cannot write the preview: " + OIIO::geterror());
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fieldcast-sculpt: a voxel model (.vox) carved from three photographs of an object"};
  std::string side, front, top, output, key, preview;
  double heightM = 0.0;
  int tolerance = 24;
  app.add_option("--side", side, "the object seen from its right: its back on the image's left")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--front", front, "the object seen from in front: its right on the image's left")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--top", top, "the object seen from above: its front up")->required()->check(CLI::ExistingFile);
  app.add_option("--height", heightM, "the object's height in metres (the side and front are scaled to it)")
      ->required()
      ->check(fieldcast::tools::finiteRange(0.5, 128.0, "m"));
  app.add_option("--key", key, "the background's colour (rrggbb); without it the images' alpha channel")
      ->check(hexColour());
  app.add_option("--key-tolerance", tolerance, "largest channel difference from the key still background")
      ->check(fieldcast::tools::intRange(0, 255, ""))
      ->capture_default_str();
  app.add_option("-o,--output", output, "the .vox file to write")->required();
  app.add_option("--preview", preview, "also write the model's side, front and top views as an image");
  CLI11_PARSE(app, argc, argv);

  try {
    BackgroundKey background;
    if (!key.empty()) background.keyRgb = parseHex(key);
    background.tolerance = tolerance;
    const SculptViews views{readSilhouette(side, background), readSilhouette(front, background),
                            readSilhouette(top, background)};
    const SculptResult r = sculptFromSilhouettes(views, heightM);
    const VoxWriteReport written = writeVoxFile(output, r.solid);
    std::printf(
        "%s: %d x %d x %d voxels of %.2f m (%.2f m wide, %.2f m deep, %.2f m high; the top view's aspect "
        "within %.1f%%)\n",
        output.c_str(), r.solid.sizeX, r.solid.sizeY, r.solid.sizeZ, kSolidVoxelM, r.widthM, r.depthM, r.heightM,
        100.0 * r.topAspectError);
    std::printf("%s: %zu voxels: %zu coloured from the top, %zu from the side, %zu from the front, %zu hidden\n",
                output.c_str(), r.solid.filledCount(), r.fromTop, r.fromSide, r.fromFront, r.hidden);
    std::printf("%s: palette of %d colours (%s)\n", output.c_str(), written.paletteEntries,
                written.maxColourError == 0
                    ? "exact"
                    : ("median cut, a channel off by " + std::to_string(written.maxColourError) + " at most").c_str());
    if (!preview.empty()) writePreview(preview, r.solid);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fieldcast-sculpt: %s\n", e.what());
    return 1;
  }
  return 0;
}
