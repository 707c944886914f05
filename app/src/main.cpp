// fieldcast — the real-time image generator service.
#include "ServiceConfig.h"

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>
#include <vector>

namespace {

int run(int argc, char** argv) {
  CLI::App cli{
      "fieldcast: a real-time image generator. Renders voxel terrain by ray casting, warps the newest\n"
      "frame to every video field's display time and emits fields at a fixed rate (59.94, 60 or 50 Hz).",
      "fieldcast"};
  std::string configPath = FIELDCAST_DEFAULT_CONFIG;
  std::vector<std::string> overrides;
  bool checkOnly = false;
  cli.add_option("-c,--config", configPath, "Configuration file (TOML); every key is in config/README.md")
      ->capture_default_str();
  cli.add_option("--set", overrides, "Override a key: --set output.rate=50 (repeatable)");
  cli.add_flag("--check-config", checkOnly, "Validate the configuration, print a summary and exit");
  cli.set_version_flag("--version", std::string("fieldcast ") + FIELDCAST_VERSION);
  CLI11_PARSE(cli, argc, argv);

  try {
    const auto config = fieldcast::app::loadServiceConfig(configPath, overrides);
    std::printf("%s\n", fieldcast::app::describe(config).c_str());
    if (checkOnly) {
      std::printf("configuration OK\n");
      return 0;
    }
    spdlog::error("the render/warp/output pipeline is not built yet; only --check-config is available");
    return 2;
  } catch (const fieldcast::app::ConfigError& e) {
    std::fprintf(stderr, "fieldcast: %s\n", e.what());
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fieldcast: fatal: %s\n", e.what());
    return 1;
  } catch (...) {
    std::fprintf(stderr, "fieldcast: fatal: unknown exception\n");
    return 1;
  }
}
