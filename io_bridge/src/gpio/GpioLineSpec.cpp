#include <io_bridge/GpioInput.h>

#include <charconv>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace fieldcast::io {

GpioLineConfig parseGpioLineSpec(const std::string& spec) {
  const auto fail = [&](const std::string& what) { throw std::runtime_error("GPIO line \"" + spec + "\": " + what); };
  std::vector<std::string_view> parts;
  std::string_view rest(spec);
  for (;;) {
    const auto colon = rest.find(':');
    parts.push_back(rest.substr(0, colon));
    if (colon == std::string_view::npos) break;
    rest.remove_prefix(colon + 1);
  }
  if (parts.size() < 2 || parts[0].empty()) fail("expected chip:offset[:active_low][:pull_up|:pull_down|:bias_off]");
  GpioLineConfig c;
  c.chip = std::string(parts[0]);
  unsigned offset = 0;
  const auto [end, ec] = std::from_chars(parts[1].data(), parts[1].data() + parts[1].size(), offset);
  if (ec != std::errc{} || end != parts[1].data() + parts[1].size()) {
    fail("line offset \"" + std::string(parts[1]) + "\" is not a number");
  }
  c.offset = offset;
  bool biasGiven = false;
  for (std::size_t i = 2; i < parts.size(); ++i) {
    const std::string_view p = parts[i];
    if (p == "active_low") {
      c.activeLow = true;
      continue;
    }
    GpioBias bias = GpioBias::AsIs;
    if (p == "pull_up") {
      bias = GpioBias::PullUp;
    } else if (p == "pull_down") {
      bias = GpioBias::PullDown;
    } else if (p == "bias_off") {
      bias = GpioBias::Disable;
    } else {
      fail("unknown flag \"" + std::string(p) + "\" (expected active_low, pull_up, pull_down or bias_off)");
    }
    if (biasGiven) fail("more than one bias flag");
    biasGiven = true;
    c.bias = bias;
  }
  return c;
}

}  // namespace fieldcast::io
