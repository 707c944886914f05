// Profiles and mapping: shaping functions, the generic profile on a real descriptor, profile files
// and their error messages, and the hand-over to the flight model.
#include <io_bridge/HidReportDecoder.h>
#include <io_bridge/InputConfig.h>
#include <io_bridge/StickMapper.h>
#include <io_bridge/StickProfile.h>

#include <motion/FlightModel.h>

#include "FakeInputSource.h"
#include "RealDescriptors.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace fieldcast::io {
namespace {

using namespace usages;
using testing::frame;
using testing::plainStick;

TEST(StickShaping, BipolarCentreEndsDeadZoneAndExpo) {
  AxisCalibration c{0, 1000, 500, false, 0.0, 0.0};
  EXPECT_DOUBLE_EQ(shapeBipolar(500, c), 0.0);
  EXPECT_DOUBLE_EQ(shapeBipolar(1000, c), 1.0);
  EXPECT_DOUBLE_EQ(shapeBipolar(0, c), -1.0);
  EXPECT_DOUBLE_EQ(shapeBipolar(2000, c), 1.0);  // beyond calibration: clamped
  EXPECT_DOUBLE_EQ(shapeBipolar(750, c), 0.5);
  c.invert = true;
  EXPECT_DOUBLE_EQ(shapeBipolar(750, c), -0.5);
  c.invert = false;
  c.deadZone = 0.1;
  EXPECT_DOUBLE_EQ(shapeBipolar(540, c), 0.0);      // inside the dead zone
  EXPECT_NEAR(shapeBipolar(551, c), 0.0022, 1e-3);  // continuous at its edge
  EXPECT_DOUBLE_EQ(shapeBipolar(1000, c), 1.0);     // full travel still reaches 1
  c.deadZone = 0.0;
  c.expo = 1.0;
  EXPECT_DOUBLE_EQ(shapeBipolar(750, c), 0.125);  // cubic
  EXPECT_DOUBLE_EQ(shapeBipolar(250, c), -0.125);
  // An off-centre calibration: each side scales on its own.
  AxisCalibration skew{0, 1000, 200, false, 0.0, 0.0};
  EXPECT_DOUBLE_EQ(shapeBipolar(100, skew), -0.5);
  EXPECT_DOUBLE_EQ(shapeBipolar(600, skew), 0.5);
}

TEST(StickShaping, UnipolarThrottle) {
  AxisCalibration c{0, 255, 128, true, 0.0, 0.0};
  EXPECT_DOUBLE_EQ(shapeUnipolar(0, c), 1.0);  // lever forward reads the minimum: full power
  EXPECT_DOUBLE_EQ(shapeUnipolar(255, c), 0.0);
  c.invert = false;
  c.deadZone = 0.1;
  EXPECT_DOUBLE_EQ(shapeUnipolar(10, c), 0.0);
  EXPECT_DOUBLE_EQ(shapeUnipolar(250, c), 1.0);
  EXPECT_NEAR(shapeUnipolar(128, c), 0.5, 0.01);
  // The widest dead zone a profile takes leaves no travel: a switch at the middle, never NaN
  c.max = 254;
  c.deadZone = 0.5;
  EXPECT_EQ(shapeUnipolar(127, c), 0.0);
  EXPECT_EQ(shapeUnipolar(126, c), 0.0);
  EXPECT_EQ(shapeUnipolar(128, c), 1.0);
}

TEST(StickMapper, GenericProfileOnTheTcaYokeDescriptor) {
  // The whole chain: real descriptor → report → events → ControlState.
  HidInputTranslator translator(parseHidReportDescriptor(testdata::kTcaYokeBoeing));
  DeviceDescription device;
  device.name = "TCA YOKE BOEING";
  device.controls = translator.controls();
  StickMapper mapper(device, StickProfile::generic());
  std::vector<std::uint8_t> report(64, 0);
  report[0] = 0x01;
  report[1] = 0x06 | 0x10;               // hat West, button 1
  report[4] = 0xff, report[5] = 0xff;    // Y fully back: nose up
  report[6] = 0x00, report[7] = 0x00;    // X fully left: roll left
  report[14] = 0x00, report[15] = 0xC0;  // Rz 0xC000: a quarter right
  std::vector<InputEvent> events;
  ASSERT_EQ(translator.translate(report, 42, events).status, HidDecodeStatus::Ok);
  bool framed = false;
  for (const InputEvent& e : events) framed = mapper.apply(e) || framed;
  ASSERT_TRUE(framed);
  const ControlState& s = mapper.state();
  EXPECT_EQ(s.time, TimePoint{Nanoseconds{42}});
  EXPECT_DOUBLE_EQ(s.roll, -1.0);
  EXPECT_DOUBLE_EQ(s.pitch, 1.0);
  EXPECT_NEAR(s.yaw, (0.5 - 0.05) / 0.95, 1e-4);  // half travel right, less the dead zone
  EXPECT_DOUBLE_EQ(s.throttle, 1.0);              // generic takes the yoke's Z (reported 0, inverted)
  EXPECT_TRUE(s.button(1));
  EXPECT_FALSE(s.button(2));
  EXPECT_EQ(s.hat, 6);
  EXPECT_EQ(s.health, InputHealth::Live);
  EXPECT_NE(mapper.describeBindings().find("throttle: Z [0, 65535]"), std::string::npos);
  // The shipped yoke profile leaves the throttle to the quadrant: the default applies.
  const StickProfile yoke =
      loadStickProfile(std::filesystem::path(FIELDCAST_SOURCE_DIR) / "config/sticks/tca_yoke_boeing.toml");
  StickMapper yokeMapper(device, yoke);
  for (const InputEvent& e : events) yokeMapper.apply(e);
  EXPECT_DOUBLE_EQ(yokeMapper.state().throttle, 0.6);
  EXPECT_NE(yokeMapper.describeBindings().find("throttle: unbound"), std::string::npos);
}

TEST(StickMapper, UnreportedControlsAreNeutralAndButtonOrderApplies) {
  StickProfile p = StickProfile::generic();
  p.buttonOrder = {3, 1};  // ControlState button 1 = device button 3
  StickMapper m(plainStick(), p);
  for (const auto& e : frame(1, {{button(3), 1}, {button(2), 1}})) m.apply(e);
  EXPECT_DOUBLE_EQ(m.state().roll, 0.0);
  EXPECT_DOUBLE_EQ(m.state().throttle, 0.5);  // lever not reported yet: the default
  EXPECT_EQ(m.state().buttons, 1u);           // device button 2 is not in the order
  for (const auto& e : frame(2, {{kThrottle, 0}})) m.apply(e);
  EXPECT_DOUBLE_EQ(m.state().throttle, 1.0);
}

TEST(StickProfile, ParsesAFileAndNamesTheLineOfAnError) {
  const char* text = R"(name = "Test yoke"
match = ["YOKE"]
default_throttle = 0.3
[roll]
control = ["usage:0x0001:0x0031", "x"]
invert = true
min = 100
max = 900
dead_zone = 0.05
expo = 0.4
[throttle]
control = "abs:0x28"
[buttons]
order = [2, 1]
[loss]
decay_s = 0.5
throttle = "neutral"
)";
  const StickProfile p = parseStickProfile(text, "yoke.toml");
  EXPECT_EQ(p.name, "Test yoke");
  EXPECT_EQ(p.axis(AxisRole::Roll).controls, (std::vector<Usage>{kY, kX}));
  EXPECT_TRUE(p.axis(AxisRole::Roll).invert);
  EXPECT_EQ(p.axis(AxisRole::Roll).min, 100);
  EXPECT_DOUBLE_EQ(p.axis(AxisRole::Roll).expo, 0.4);
  EXPECT_EQ(p.axis(AxisRole::Throttle).controls, (std::vector<Usage>{makeUsage(kEvdevAbsPage, 0x28)}));
  EXPECT_EQ(p.axis(AxisRole::Pitch).controls, (std::vector<Usage>{kY}));  // generic where not given
  EXPECT_EQ(p.buttonOrder, (std::vector<std::uint16_t>{2, 1}));
  EXPECT_EQ(p.throttleOnLoss, ThrottleOnLoss::Neutral);

  auto errorOf = [](const char* bad) {
    try {
      (void)parseStickProfile(bad, "bad.toml");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(errorOf("[roll]\ndead_zone = 2\n"), "bad.toml:2: roll.dead_zone: expected a number from 0 to 0.5, got 2");
  EXPECT_EQ(errorOf("[pitch]\ninvert = true\nexpo = 0.1\nfoo = 1\n"),
            "bad.toml:4: pitch.foo: unknown key (expected one of: center, control, dead_zone, expo, invert, max, min)");
  EXPECT_NE(errorOf("[yaw]\ncontrol = \"twist\"\n").find("bad.toml:2: yaw.control: expected x, y"), std::string::npos);
  EXPECT_EQ(errorOf("[roll]\nmin = 10\nmax = 5\n"), "bad.toml:3: roll.max: expected more than min (10), got 5");
  EXPECT_EQ(errorOf("[loss]\nthrottle = \"cut\"\n"),
            "bad.toml:2: loss.throttle: expected one of \"hold\", \"neutral\", got \"cut\"");
  EXPECT_NE(errorOf("name = \n").find("bad.toml:1:"), std::string::npos);
}

TEST(StickProfile, ButtonsMapTheCockpitActions) {
  const StickProfile p = parseStickProfile("[buttons]\nfreeze = 2\nreset = 3\ntrigger = 64\n", "b.toml");
  EXPECT_EQ(p.cockpit.freeze, 2);
  EXPECT_EQ(p.cockpit.reset, 3);
  EXPECT_EQ(p.cockpit.trigger, 64);
  const StickProfile none = parseStickProfile("[buttons]\norder = [2, 1]\n", "b.toml");
  EXPECT_EQ(none.cockpit.freeze + none.cockpit.reset + none.cockpit.trigger, 0);  // unmapped
  auto errorOf = [](const char* bad) {
    try {
      (void)parseStickProfile(bad, "bad.toml");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(errorOf("[buttons]\nfreeze = 0\n"), "bad.toml:2: buttons.freeze: expected an integer from 1 to 64, got 0");
  EXPECT_EQ(errorOf("[buttons]\nreset = 65\n"), "bad.toml:2: buttons.reset: expected an integer from 1 to 64, got 65");
  EXPECT_NE(errorOf("[buttons]\ntrigger = \"a\"\n").find("bad.toml:2: buttons.trigger:"), std::string::npos);
  EXPECT_NE(errorOf("[buttons]\nfire = 1\n").find("bad.toml:2: buttons.fire: unknown key"), std::string::npos);
  // The shipped Raptor profile maps all three.
  const StickProfile raptor =
      loadStickProfile(std::filesystem::path(FIELDCAST_SOURCE_DIR) / "config" / "sticks" / "raptor_mach2.toml");
  EXPECT_EQ(raptor.cockpit.trigger, 1);
  EXPECT_EQ(raptor.cockpit.freeze, 5);
  EXPECT_EQ(raptor.cockpit.reset, 6);
}

TEST(InputConfig, ReadsTheCockpitDiscreteLines) {
  const auto read = [](const char* text) {
    ConfigReader top = ConfigDocument::parseText(text, "in.toml").root();
    ConfigReader input = top.table("input");
    return readInputConfig(input);
  };
  const InputConfig c = read(
      "[input]\nsync = \"gpiochip0:4\"\nfreeze = \"gpiochip0:5\"\nreset = \"gpiochip0:6:active_low\"\n"
      "trigger = \"gpiochip1:7\"\n");
  EXPECT_EQ(c.sync, "gpiochip0:4");
  EXPECT_EQ(c.freeze, "gpiochip0:5");
  EXPECT_EQ(c.reset, "gpiochip0:6:active_low");
  EXPECT_EQ(c.trigger, "gpiochip1:7");
  EXPECT_TRUE(read("[input]\n").freeze.empty());
}

TEST(StickProfile, ShippedProfilesParse) {
  const std::filesystem::path dir = std::filesystem::path(FIELDCAST_SOURCE_DIR) / "config" / "sticks";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".toml") continue;
    EXPECT_NO_THROW((void)loadStickProfile(entry.path())) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 3);
  EXPECT_THROW((void)loadStickProfile(dir / "no-such.toml"), std::runtime_error);
}

TEST(StickMapper, ControlStateDrivesTheFlightModel) {
  StickMapper m(plainStick(), StickProfile::generic());
  for (const auto& e : frame(1, {{kX, 1023}, {kY, 512}, {kRz, 512}, {kThrottle, 0}})) m.apply(e);
  const ControlState& s = m.state();
  const motion::FlightControls controls{s.roll, s.pitch, s.yaw, s.throttle};  // the whole mapping
  motion::FlightModel model(motion::FlightModelParams{}, Pose{}, 100.0, TimePoint{});
  model.step(TimePoint{std::chrono::milliseconds(100)}, controls);
  EXPECT_GT(model.state().pose.rollRad, 0.1);  // stick right: right wing down
  EXPECT_GT(model.state().speedMps, 100.0);    // full throttle: speeding up
}

}  // namespace
}  // namespace fieldcast::io
