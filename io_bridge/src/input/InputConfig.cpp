#include <io_bridge/InputConfig.h>

namespace fieldcast::io {

InputConfig readInputConfig(ConfigReader& t) {
  InputConfig c;
  c.stick = t.string("stick", "");
  c.profile = t.path("profile", "");
  c.record = t.path("record", "");
  c.sync = t.string("sync", "");
  c.freeze = t.string("freeze", "");
  c.reset = t.string("reset", "");
  c.trigger = t.string("trigger", "");
  t.finish();
  return c;
}

}  // namespace fieldcast::io
