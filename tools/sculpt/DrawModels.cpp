// The drawings the shipped sculpted models were made from (config/models/README.md): a delivery
// van, a cottage and a light aircraft, each as the three orthographic views fieldcast-sculpt takes (Sculpt.h), drawn
// to scale (100 px a metre) on a green key. Made by the project; run it to make them again:
//   fieldcast-draw-models config/models
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace {

constexpr double kPxPerM = 100.0;
constexpr int kMarginPx = 40;
const cv::Scalar kKey(0, 255, 0);  // BGR

// A view widthM × heightM metres: a canvas with the key around; points in metres from its
// bottom-left (across, up)
class Drawing {
 public:
  Drawing(double widthM, double heightM)
      : mHeightM(heightM),
        mImage(static_cast<int>(heightM * kPxPerM) + 2 * kMarginPx, static_cast<int>(widthM * kPxPerM) + 2 * kMarginPx,
               CV_8UC3, kKey) {}
  cv::Point at(double a, double up) const {
    return {kMarginPx + static_cast<int>(a * kPxPerM + 0.5),
            kMarginPx + static_cast<int>((mHeightM - up) * kPxPerM + 0.5)};
  }
  void box(double a0, double up0, double a1, double up1, const cv::Scalar& bgr) {
    cv::rectangle(mImage, at(a0, up1), at(a1, up0) - cv::Point(1, 1), bgr, cv::FILLED, cv::LINE_8);
  }
  void polygon(const std::vector<std::pair<double, double>>& points, const cv::Scalar& bgr) {
    std::vector<cv::Point> px;
    for (const auto& [a, up] : points) px.push_back(at(a, up));
    cv::fillPoly(mImage, std::vector<std::vector<cv::Point>>{px}, bgr, cv::LINE_8);
  }
  void disc(double a, double up, double radiusM, const cv::Scalar& bgr) {
    cv::circle(mImage, at(a, up), static_cast<int>(radiusM * kPxPerM), bgr, cv::FILLED, cv::LINE_8);
  }
  void line(double a0, double up0, double a1, double up1, const cv::Scalar& bgr, int px = 3) {
    cv::line(mImage, at(a0, up0), at(a1, up1), bgr, px, cv::LINE_8);
  }
  void save(const std::filesystem::path& path) const {
    if (!cv::imwrite(path.string(), mImage)) throw std::runtime_error(path.string() + ": cannot write");
    std::printf("%s: %d x %d px\n", path.string().c_str(), mImage.cols, mImage.rows);
  }

 private:
  double mHeightM;
  cv::Mat mImage;
};

cv::Scalar rgb(int r, int g, int b) { return {static_cast<double>(b), static_cast<double>(g), static_cast<double>(r)}; }

// A delivery van 2.0 m wide, 5.0 m long, 2.4 m high: a red box body, the cab's windscreen
// sloping down to a short bonnet, on four wheels
void drawVan(const std::filesystem::path& dir) {
  const cv::Scalar body = rgb(196, 32, 28), roof = rgb(214, 206, 200), glass = rgb(40, 56, 72), tyre = rgb(30, 30, 30),
                   hub = rgb(150, 150, 150), lamp = rgb(250, 240, 190), trim = rgb(60, 60, 60);
  Drawing side(5.0, 2.4);  // the back on the left
  side.polygon({{0.0, 0.35}, {0.0, 2.4}, {3.9, 2.4}, {4.5, 1.3}, {5.0, 1.1}, {5.0, 0.35}}, body);
  side.polygon({{3.95, 2.25}, {4.4, 1.35}, {3.9, 1.35}, {3.9, 2.25}}, glass);  // the cab's side window
  side.box(0.0, 1.45, 3.85, 1.6, roof);                                        // a stripe along the body
  side.line(3.3, 0.4, 3.3, 2.3, trim);                                         // the sliding door's edge
  side.box(4.7, 0.8, 5.0, 0.95, lamp);
  for (double y : {0.9, 4.1}) side.disc(y, 0.35, 0.35, tyre), side.disc(y, 0.35, 0.15, hub);
  side.save(dir / "side.png");

  Drawing front(2.0, 2.4);  // the van's right on the left
  front.box(0.0, 0.35, 2.0, 2.4, body);
  front.polygon({{0.15, 1.3}, {1.85, 1.3}, {1.75, 2.25}, {0.25, 2.25}}, glass);  // the windscreen
  front.box(0.6, 0.55, 1.4, 0.95, trim);                                         // the grille
  front.box(0.1, 0.75, 0.45, 0.95, lamp);
  front.box(1.55, 0.75, 1.9, 0.95, lamp);
  front.box(0.0, 0.35, 2.0, 0.5, trim);  // the bumper
  front.box(0.1, 0.0, 0.4, 0.35, tyre);
  front.box(1.6, 0.0, 1.9, 0.35, tyre);
  front.save(dir / "front.png");

  Drawing top(2.0, 5.0);  // the front up
  top.box(0.0, 0.0, 2.0, 3.9, roof);
  for (double y = 0.4; y < 3.8; y += 0.7) top.line(0.2, y, 1.8, y, rgb(170, 164, 160));  // the roof's ribs
  top.polygon({{0.0, 3.9}, {2.0, 3.9}, {2.0, 4.5}, {0.0, 4.5}}, glass);
  top.box(0.0, 4.5, 2.0, 5.0, body);
  top.save(dir / "top.png");
}

// A cottage 9 m wide and 6 m deep: whitewashed walls to the eaves at 3.5 m, a tiled roof with its
// ridge across the front at 7 m, a brick chimney at the right gable to 8 m
void drawCottage(const std::filesystem::path& dir) {
  const cv::Scalar wall = rgb(236, 230, 214), tile = rgb(150, 64, 44), tileLine = rgb(112, 46, 32),
                   brick = rgb(120, 70, 56), glass = rgb(52, 70, 92), door = rgb(40, 80, 60),
                   frame = rgb(250, 250, 250);
  Drawing front(9.0, 8.0);  // the cottage's right (and its chimney) on the left
  front.box(0.0, 0.0, 9.0, 3.5, wall);
  front.box(0.0, 3.5, 9.0, 7.0, tile);
  for (double z = 3.9; z < 7.0; z += 0.45) front.line(0.0, z, 9.0, z, tileLine);
  front.box(0.2, 7.0, 1.0, 8.0, brick);
  front.box(4.0, 0.0, 5.0, 2.1, door);
  for (double x : {1.2, 2.6, 6.0, 7.4})
    front.box(x - 0.1, 0.9, x + 1.0, 2.5, frame), front.box(x, 1.0, x + 0.9, 2.4, glass);
  front.save(dir / "front.png");

  Drawing side(6.0, 8.0);  // the back on the left; the gable end
  side.box(0.0, 0.0, 6.0, 3.5, wall);
  side.polygon({{0.0, 3.5}, {6.0, 3.5}, {3.0, 7.0}}, wall);
  side.line(0.0, 3.5, 3.0, 7.0, tile, 12);  // the verge tiles along the gable's edges
  side.line(3.0, 7.0, 6.0, 3.5, tile, 12);
  side.box(2.6, 5.6, 3.4, 8.0, brick);
  side.box(2.55, 4.0, 3.45, 5.0, frame), side.box(2.65, 4.1, 3.35, 4.9, glass);  // the attic window
  side.box(3.8, 0.9, 4.9, 2.5, frame), side.box(3.9, 1.0, 4.8, 2.4, glass);
  side.save(dir / "side.png");

  Drawing top(9.0, 6.0);  // the front up
  top.box(0.0, 3.0, 9.0, 6.0, tile);
  top.box(0.0, 0.0, 9.0, 3.0, rgb(128, 54, 38));  // the back slope, in its own light
  for (double x = 0.3; x < 9.0; x += 0.6) top.line(x, 0.0, x, 6.0, tileLine);
  top.line(0.0, 3.0, 9.0, 3.0, rgb(90, 40, 30), 8);  // the ridge
  top.box(8.0, 2.6, 8.8, 3.4, brick);
  top.save(dir / "top.png");
}

// A high-wing light aircraft 11.5 m in span, 8 m long, 3 m to the top of its fin: a white
// fuselage with a blue cheat line, the wing on top of the cabin, a fixed tricycle undercarriage
void drawAircraft(const std::filesystem::path& dir) {
  const cv::Scalar white = rgb(238, 238, 232), blue = rgb(30, 70, 160), glass = rgb(50, 66, 90), tyre = rgb(30, 30, 30),
                   prop = rgb(70, 70, 70), wing = rgb(228, 228, 220), tip = rgb(200, 40, 30);
  Drawing side(8.0, 3.0);  // the tail on the left, the nose on the right
  side.polygon(
      {{0.0, 1.55}, {0.0, 1.85}, {4.4, 2.0}, {6.6, 2.0}, {7.6, 1.75}, {7.9, 1.4}, {7.6, 0.9}, {5.0, 0.7}, {1.0, 1.3}},
      white);
  side.polygon({{0.0, 1.8}, {0.35, 3.0}, {1.2, 3.0}, {1.9, 1.8}}, white);  // the fin
  side.box(0.2, 2.55, 1.0, 2.95, blue);
  side.box(4.6, 2.0, 6.2, 2.4, wing);                                       // the wing, edge on
  side.polygon({{6.2, 1.95}, {6.6, 1.95}, {7.3, 1.6}, {6.4, 1.6}}, glass);  // the windscreen
  side.box(4.7, 1.55, 6.1, 1.95, glass);                                    // the cabin's side windows
  side.line(0.3, 1.5, 7.8, 1.3, blue, 8);                                   // the cheat line
  side.box(7.9, 0.6, 8.0, 2.2, prop);
  side.line(5.6, 0.9, 5.3, 0.35, tyre, 6);
  side.disc(5.2, 0.25, 0.25, tyre);
  side.line(7.3, 0.9, 7.3, 0.35, tyre, 6);
  side.disc(7.3, 0.22, 0.22, tyre);
  side.save(dir / "side.png");

  Drawing front(11.5, 3.0);  // the aircraft's right on the left; the fin one voxel wide on the middle
  front.box(0.0, 2.0, 11.5, 2.4, wing);
  front.box(0.0, 2.0, 0.4, 2.4, tip);
  front.box(11.1, 2.0, 11.5, 2.4, tip);
  front.box(4.15, 1.5, 7.35, 1.8, white);  // the tailplane behind
  front.box(5.5, 2.4, 6.0, 3.0, white);    // the fin above the wing
  front.polygon({{5.15, 0.8}, {6.35, 0.8}, {6.45, 2.0}, {5.05, 2.0}}, white);
  front.box(5.25, 1.6, 6.25, 1.95, glass);
  front.disc(5.75, 1.4, 0.8, prop);  // the propeller's disc
  front.box(5.6, 1.25, 5.9, 1.55, white);
  for (double x : {4.35, 5.6, 6.85}) front.box(x, 0.0, x + 0.3, 0.5, tyre);
  front.line(4.5, 0.45, 5.15, 0.9, tyre, 6);
  front.line(7.0, 0.45, 6.35, 0.9, tyre, 6);
  front.save(dir / "front.png");

  Drawing top(11.5, 8.0);  // the nose up
  top.polygon({{5.45, 0.0}, {6.05, 0.0}, {6.3, 6.0}, {6.15, 7.9}, {5.35, 7.9}, {5.2, 6.0}}, white);
  top.box(4.15, 0.1, 7.35, 1.1, white);  // the tailplane
  top.box(0.0, 4.6, 11.5, 6.2, wing);
  top.box(0.0, 4.6, 0.4, 6.2, tip);
  top.box(11.1, 4.6, 11.5, 6.2, tip);
  top.line(5.75, 0.2, 5.75, 4.5, blue, 8);  // the spine's stripe
  top.box(5.35, 6.3, 6.15, 7.2, glass);
  top.save(dir / "top.png");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fieldcast-draw-models <folder>   (writes <folder>/{van,cottage,aircraft}/*.png)\n");
    return 2;
  }
  try {
    const std::filesystem::path root = argv[1];
    std::filesystem::create_directories(root / "van");
    std::filesystem::create_directories(root / "cottage");
    std::filesystem::create_directories(root / "aircraft");
    drawVan(root / "van");
    drawCottage(root / "cottage");
    drawAircraft(root / "aircraft");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fieldcast-draw-models: %s\n", e.what());
    return 1;
  }
  return 0;
}
