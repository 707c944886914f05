#include <motion/FlightFile.h>

#include <fieldcast/ConfigReader.h>

#include <stdexcept>
#include <utility>

namespace fieldcast::motion {
namespace {

FlightEnd readEnd(ConfigReader& t) {
  return t.choice("end", FlightEnd::Loop,
                  {{"loop", FlightEnd::Loop}, {"hold", FlightEnd::Hold}, {"stop", FlightEnd::Stop}});
}

// The [[waypoint]] tables of `t` (at least two)
std::vector<Waypoint> readWaypoints(ConfigReader& t, const std::string& what) {
  std::vector<ConfigReader> tables = t.tables("waypoint");
  if (tables.size() < 2) t.fail("waypoint", "expected at least two [[" + what + "]] tables");
  std::vector<Waypoint> waypoints;
  constexpr double kMaxAbs = 1e9;  // any finite value a flight file could mean
  for (ConfigReader& w : tables) {
    Waypoint p;
    if (!w.has("t") || !w.has("position")) w.fail("t", "t and position are required");
    p.timeS = w.number("t", 0.0, -kMaxAbs, kMaxAbs);
    const std::vector<double> xyz = w.numbers("position", {}, 3);
    p.positionM = {xyz[0], xyz[1], xyz[2]};
    // An angle left out follows the path (see ScriptedTrajectory.h).
    if (w.has("heading_deg")) p.headingRad = radians(w.number("heading_deg", 0.0, -kMaxAbs, kMaxAbs));
    if (w.has("pitch_deg")) p.pitchRad = radians(w.number("pitch_deg", 0.0, -kMaxAbs, kMaxAbs));
    if (w.has("roll_deg")) p.rollRad = radians(w.number("roll_deg", 0.0, -kMaxAbs, kMaxAbs));
    w.finish();
    waypoints.push_back(p);
  }
  return waypoints;
}

}  // namespace

FlightFile readFlightFile(const std::filesystem::path& path) {
  ConfigReader root = ConfigDocument::parseFile(path).root();
  const std::string name = root.nonEmptyString("name", "unnamed flight");
  root.string("description", "");
  const double cameraPitchDeg = root.number("camera_pitch_deg", 0.0, -90.0, 90.0);
  const FlightEnd end = readEnd(root);
  const double clearanceM = root.number("clearance_m", 15.0, 0.0, 10000.0);
  std::vector<Waypoint> waypoints = readWaypoints(root, "waypoint");
  std::vector<ConfigReader> entityTables = root.tables("entity");
  root.finish();
  const auto built = [&](const std::string& what, auto&& make) {
    try {
      return make();
    } catch (const std::invalid_argument& e) {
      throw ConfigError(path.string() + ": " + what + e.what());
    }
  };
  FlightFile file{
      built("",
            [&] { return ScriptedTrajectory(name, std::move(waypoints), radians(cameraPitchDeg), end, clearanceM); }),
      {}};
  for (ConfigReader& t : entityTables) {
    const std::string entityName = t.nonEmptyString("name", "entity " + std::to_string(file.entities.size() + 1));
    if (!t.has("model")) t.fail("model", "an entity needs a model (a .vox file)");
    const std::filesystem::path model = t.path("model", {});
    const double scale = t.number("scale", 1.0, 0.25, 4.0);
    const bool onGround = t.boolean("on_ground", false);
    const FlightEnd entityEnd = readEnd(t);
    std::vector<Waypoint> entityWaypoints = readWaypoints(t, "entity.waypoint");
    t.finish();
    file.entities.push_back(
        ScriptedEntity{entityName, model, scale, onGround, built("entity '" + entityName + "': ", [&] {
                         // No clearance floor: a vehicle drives on the ground, an aircraft flies where it is told
                         return ScriptedTrajectory(entityName, std::move(entityWaypoints), 0.0, entityEnd, 0.0);
                       })});
  }
  return file;
}

}  // namespace fieldcast::motion
