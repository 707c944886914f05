#include <motion/MotionConfig.h>

#include <vector>

namespace fieldcast::motion {

MotionConfig readMotionConfig(ConfigReader& t) {
  MotionConfig c;
  c.source = t.choice("source", c.source,
                      {{"flight", MotionKind::Flight}, {"stick", MotionKind::Stick}, {"host", MotionKind::Host}});
  c.flightPath = t.path("flight", "flights/ridge_run.toml");
  // x, y, z (m) and heading (degrees): the stick flies level from there.
  const std::vector<double> s = t.numbers(
      "start", {c.start.positionM.x, c.start.positionM.y, c.start.positionM.z, degrees(c.start.headingRad)}, 4);
  c.start = Pose{{s[0], s[1], s[2]}, radians(s[3]), 0.0, 0.0};
  c.startSpeedMps = t.number("start_speed_mps", c.startSpeedMps, 0.0, 2000.0);
  c.durationS = t.number("duration_s", c.durationS, 0.0, 1e7);
  t.finish();
  return c;
}

}  // namespace fieldcast::motion
