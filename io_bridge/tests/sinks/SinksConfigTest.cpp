// [output] and [sinks.*] as the service reads them.
#include <io_bridge/SinksConfig.h>

#include <gtest/gtest.h>

#include <string>

namespace fieldcast::io {
namespace {

ConfigReader tableOf(const std::string& text, const char* table) {
  return ConfigDocument::parseText(text, "/cfg/fieldcast.toml").root().table(table);
}

std::string errorOf(const std::string& text, const char* table, bool sinks) {
  try {
    ConfigReader t = tableOf(text, table);
    if (sinks) {
      readSinksConfig(t);
    } else {
      readStreamFormat(t);
    }
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SinksConfig, OutputRatesAreTheThreeVideoRates) {
  ConfigReader ntsc = tableOf("[output]\n", "output");
  const StreamFormat f = readStreamFormat(ntsc);
  EXPECT_EQ(f.fieldRate.numerator, 60000);
  EXPECT_EQ(f.fieldRate.denominator, 1001);
  EXPECT_EQ(f.pixelAspect, (PixelAspect{10, 11}));  // 720×486
  ConfigReader pal = tableOf("[output]\nrate = 50\nheight = 576\nscan = \"progressive\"\n", "output");
  const StreamFormat p = readStreamFormat(pal);
  EXPECT_EQ(p.fieldRate.numerator, 50);
  EXPECT_EQ(p.fieldRate.denominator, 1);
  EXPECT_EQ(p.scan, ScanMode::Progressive);
  EXPECT_EQ(p.pixelAspect, (PixelAspect{12, 11}));
  EXPECT_EQ(errorOf("[output]\nrate = 61\n", "output", false),
            "/cfg/fieldcast.toml:2: output.rate: expected 50, 59.94 or 60, got 61");
  EXPECT_EQ(errorOf("[output]\nwidth = 721\n", "output", false),
            "/cfg/fieldcast.toml:2: output.width: expected an even width (4:2:2 pairs pixels), got 721");
}

TEST(SinksConfig, AnOutputIsPresentOnlyWhenEnabledAndItsKeysAreCheckedEitherWay) {
  ConfigReader t = tableOf(
      "[sinks.y4m]\nenabled = true\npath = \"out/a.y4m\"\nchroma = \"422\"\n[sinks.rtp]\nport = 6000\n", "sinks");
  const SinksConfig c = readSinksConfig(t);
  ASSERT_TRUE(c.y4m.has_value());
  EXPECT_EQ(c.y4m->path, std::filesystem::path("/cfg/out/a.y4m"));  // relative to the file
  EXPECT_EQ(c.y4m->chroma, Y4mChroma::C422);
  EXPECT_FALSE(c.rtp.has_value());
  EXPECT_FALSE(c.window);
  EXPECT_EQ(errorOf("[sinks.rtp]\nport = 70000\n", "sinks", true),
            "/cfg/fieldcast.toml:2: sinks.rtp.port: expected an integer from 1 to 65535, got 70000");
  EXPECT_EQ(errorOf("[sinks.shm]\nname = \"no-slash\"\n", "sinks", true),
            "/cfg/fieldcast.toml:2: sinks.shm.name: expected a POSIX shared-memory name like \"/fieldcast\", got "
            "\"no-slash\"");
  EXPECT_NE(errorOf("[sinks.y4m]\npaht = \"x\"\n", "sinks", true).find("sinks.y4m.paht: unknown key"),
            std::string::npos);
}

TEST(SinksConfig, MakeSinksHoldsEveryEnabledOutput) {
  const std::string dir = testing::TempDir() + "sinks_config_make";
  ConfigReader t = tableOf("[sinks.y4m]\nenabled = true\npath = \"" + dir +
                               "/v.y4m\"\n[sinks.images]\nenabled = true\ndirectory = \"" + dir + "/fields\"\n",
                           "sinks");
  const SinksConfig c = readSinksConfig(t);
  Sinks sinks = makeSinks(c, StreamFormat{});
  ASSERT_NE(sinks.hub, nullptr);
  EXPECT_EQ(sinks.window, nullptr);
  EXPECT_TRUE(std::filesystem::is_directory(dir + "/fields"));  // made before anything runs
  const std::string summary = sinks.hub->summary();
  EXPECT_NE(summary.find("y4m"), std::string::npos) << summary;
  EXPECT_NE(summary.find("images"), std::string::npos) << summary;
  EXPECT_EQ(summary.find("rtp"), std::string::npos) << summary;
}

}  // namespace
}  // namespace fieldcast::io
