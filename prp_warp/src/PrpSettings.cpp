#include <prp_warp/PrpSettings.h>

#include <prp_warp/FieldClock.h>

namespace fieldcast::warp {

PrpSettings readPrpSettings(ConfigReader& t) {
  PrpSettings s;
  s.warper.warp = t.choice("kind", s.warper.warp,
                           {{"hold", WarpKind::Hold},
                            {"rotation", WarpKind::Rotation},
                            {"quadratic", WarpKind::Quadratic},
                            {"homography", WarpKind::Homography},
                            {"mesh", WarpKind::Mesh},
                            {"range3d", WarpKind::Range3d}});
  s.warper.flickerFilter = t.boolean("flicker_filter", s.warper.flickerFilter);
  s.warper.autoGain.enabled = t.boolean("auto_gain", s.warper.autoGain.enabled);
  s.warper.mirror = t.choice("mirror", s.warper.mirror,
                             {{"none", Mirror::None},
                              {"horizontal", Mirror::Horizontal},
                              {"vertical", Mirror::Vertical},
                              {"both", Mirror::Both}});
  // Converted only when given, so the default stays PrpSettings' own to the nanosecond. At least
  // the field clock's least time for a field's work, at most the longest field period (50 Hz);
  // less than this rate's field period is the service's check, which knows the rate.
  const double leastMs = toSeconds(FieldClockConfig{}.minWork) * 1e3;
  if (t.has("lead_ms")) s.lead = fromSeconds(t.number("lead_ms", toSeconds(s.lead) * 1e3, leastMs, 20.0) * 1e-3);
  t.finish();
  return s;
}

}  // namespace fieldcast::warp
