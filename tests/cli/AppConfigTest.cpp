// The fieldcast executable's configuration handling, run as a user would run it.
#include "../common/RunFieldcast.h"

#include <fieldcast/SimdLevel.h>

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

using fieldcast::testing::RunResult;
RunResult run(const std::string& args, int timeoutS = 120) { return fieldcast::testing::runFieldcast(args, timeoutS); }

std::string writeConfig(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("fieldcast_test_" + name + ".toml");
  std::ofstream(path) << text;
  return path.string();
}

/// A configuration for a short real run (a small built-in terrain cached under its own name, a
/// small raster, no real-time thread) and the flight it flies: "PATH --flight FLIGHT".
std::string smallRun(const std::string& name) {
  const auto cache = std::filesystem::temp_directory_path() / ("fieldcast_test_" + name + "_cache");
  return writeConfig(name, "[terrain]\nsource = \"builtin\"\ncache_dir = \"" + cache.string() +
                               "\"\nbuiltin_size = 256\nmemory_budget_mb = 16\n"
                               "[output]\nwidth = 160\nheight = 120\n"
                               "[threads]\nrealtime_field_thread = false\n") +
         " --flight " FIELDCAST_SOURCE_DIR "/config/flights/ridge_run.toml";
}

TEST(AppConfig, ShippedConfigIsValid) {
  const auto r = run("--check-config --config " FIELDCAST_SOURCE_DIR "/config/fieldcast.toml");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("720x486 interlaced 59.940 Hz uyvy422"), std::string::npos) << r.output;
  const auto hd = run("--check-config --config " FIELDCAST_SOURCE_DIR "/config/fieldcast-1080i.toml");
  EXPECT_EQ(hd.exitCode, 0) << hd.output;
  EXPECT_NE(hd.output.find("1920x1080 interlaced 59.940 Hz uyvy422"), std::string::npos) << hd.output;
}

TEST(AppConfig, AnUnwritableSummaryPathIsRefusedBeforeTheRun) {
  // The summary is written at exit; a path that cannot be written must stop the service at start,
  // with one line naming it, before the terrain is opened or a field is made.
  const std::string config = smallRun("summary");
  for (const char* bad : {"/proc/fieldcast/summary.json", "/dev/null/summary.json"}) {
    const auto r = run("--config " + config + " --duration 30 --summary " + bad);
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find(std::string("fieldcast: metrics.summary_json: cannot write ") + bad), std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("terrain:"), std::string::npos) << "the terrain was opened first:\n" << r.output;
    EXPECT_EQ(r.output.find("start-up:"), std::string::npos) << "fields were started:\n" << r.output;
  }
  // A writable one in a folder that does not exist yet is fine (the folder is made), and nothing
  // is left there when the run stops before it starts (--check-config does not run).
  const auto fresh = std::filesystem::temp_directory_path() / "fieldcast_test_summary_dir" / "s.json";
  std::filesystem::remove_all(fresh.parent_path());
  const auto ok = run("--config " + config + " --duration 0.2 --summary " + fresh.string());
  EXPECT_EQ(ok.exitCode, 0) << ok.output;
  EXPECT_TRUE(std::filesystem::exists(fresh)) << ok.output;
}

TEST(AppConfig, TheSimdLevelIsCheckedAndTheOneRunIsLogged) {
  const auto bad = run("--check-config --simd avx1024");
  EXPECT_NE(bad.exitCode, 0) << bad.output;
  EXPECT_NE(bad.output.find("fieldcast: --simd: SIMD level \"avx1024\" is not one this machine runs (it has: "),
            std::string::npos)
      << bad.output;
  // The narrowest level the build has: "scalar", unless it was built for this CPU (FIELDCAST_NATIVE)
  const std::string narrowest = fieldcast::simdLevels().back();
  EXPECT_NE(bad.output.find(narrowest + ", or auto)"), std::string::npos) << bad.output;
  const std::string config = smallRun("simd");
  const auto forced = run("--config " + config + " --duration 0.2 --simd " + narrowest);
  EXPECT_EQ(forced.exitCode, 0) << forced.output;
  EXPECT_NE(forced.output.find("SIMD level " + narrowest + " (this CPU runs "), std::string::npos) << forced.output;
}

TEST(AppConfig, HelpAndVersion) {
  // --help names every option (and where the configuration keys are documented).
  const auto h = run("--help");
  EXPECT_EQ(h.exitCode, 0);
  for (const char* option : {"-c,--config", "--set", "--duration", "--flight", "--y4m", "--contact-sheet", "--summary",
                             "--rtp", "--simd", "--check-config", "--version", "--help"}) {
    EXPECT_NE(h.output.find(option), std::string::npos) << "--help does not name " << option << ":\n" << h.output;
  }
  EXPECT_NE(h.output.find("config/README.md"), std::string::npos) << h.output;
  const auto v = run("--version");
  EXPECT_EQ(v.exitCode, 0);
  EXPECT_NE(v.output.find("fieldcast "), std::string::npos);
}

TEST(AppConfig, DurationMustBeAFiniteNumberOfSeconds) {
  // -1 used to mean "not given" and NaN failed every comparison, so both ran until killed.
  for (const char* bad : {"-1", "-0.5", "nan", "inf", "-inf", "1e300"}) {
    const auto r = run(std::string("--check-config --duration ") + bad);
    EXPECT_NE(r.exitCode, 0) << "--duration " << bad << " was accepted:\n" << r.output;
    EXPECT_NE(r.output.find("--duration: expected a finite number of seconds from 0 to 1e+07 (0 = until "
                            "SIGINT/SIGTERM), got '" +
                            std::string(bad) + "'"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("configuration OK"), std::string::npos) << r.output;
  }
  for (const char* good : {"0", "20", "0.5", "1e-7"}) {
    const auto r = run(std::string("--check-config --duration ") + good);
    EXPECT_EQ(r.exitCode, 0) << "--duration " << good << ":\n" << r.output;
  }
}

TEST(AppConfig, BadRateNamesFileLineKeyAndExpectation) {
  const auto path = writeConfig("badrate", "[output]\nscan = \"interlaced\"\nrate = 61\n");
  const auto r = run("--check-config --config " + path);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find(path + ":3: output.rate: expected 50, 59.94 or 60, got 61"), std::string::npos) << r.output;
}

// [[host.database]]: each entry needs its own number, 1 to 127, not [terrain]'s; its other keys
// are [terrain]'s, checked the same way.
TEST(AppConfig, HostDatabasesNeedTheirOwnNumbers) {
  const std::string head = "[motion]\nsource = \"host\"\n[host]\ndatabase_number = 1\n";
  const auto ok = writeConfig("hostdb_ok", head +
                                               "[[host.database]]\nnumber = 2\nbuiltin_seed = 7\n"
                                               "[[host.database]]\nnumber = 3\nsource = \"/srv/valley.fctdb\"\n");
  EXPECT_EQ(run("--check-config --config " + ok).exitCode, 0);

  const auto same = writeConfig("hostdb_same", head + "[[host.database]]\nnumber = 1\n");
  RunResult r = run("--check-config --config " + same);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("number: expected a number no other database has"), std::string::npos) << r.output;

  const auto twice =
      writeConfig("hostdb_twice", head + "[[host.database]]\nnumber = 2\n[[host.database]]\nnumber = 2\n");
  r = run("--check-config --config " + twice);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find(":8:"), std::string::npos) << "the second entry's line: " << r.output;

  const auto missing = writeConfig("hostdb_missing", head + "[[host.database]]\nbuiltin_seed = 7\n");
  r = run("--check-config --config " + missing);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("expected the database's number (1 to 127)"), std::string::npos) << r.output;

  const auto typo = writeConfig("hostdb_typo", head + "[[host.database]]\nnumber = 2\nsorce = \"x.fctdb\"\n");
  r = run("--check-config --config " + typo);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("sorce: unknown key"), std::string::npos) << r.output;
}

TEST(AppConfig, UnknownKeyIsAnError) {
  const auto path = writeConfig("unknown", "[output]\nrat = 50\n");
  const auto r = run("--check-config --config " + path);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("output.rat: unknown key"), std::string::npos) << r.output;
}

TEST(AppConfig, WrongTypeIsAnError) {
  const auto path = writeConfig("wrongtype", "[output]\nwidth = \"wide\"\n");
  const auto r = run("--check-config --config " + path);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find(":2: output.width: expected an integer from 16 to 8192, got \"wide\""), std::string::npos)
      << r.output;
}

TEST(AppConfig, SyntaxErrorNamesTheLine) {
  const auto path = writeConfig("syntax", "[output]\nrate = = 5\n");
  const auto r = run("--check-config --config " + path);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find(path + ":2:"), std::string::npos) << r.output;
}

TEST(AppConfig, MissingFileIsAnError) {
  const auto r = run("--check-config --config /nonexistent/fieldcast.toml");
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("/nonexistent/fieldcast.toml"), std::string::npos) << r.output;
}

TEST(AppConfig, SetOverridesAKey) {
  const auto r = run("--check-config --config " FIELDCAST_SOURCE_DIR
                     "/config/fieldcast.toml --set output.rate=50 --set output.scan=progressive");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("progressive 50.000 Hz"), std::string::npos) << r.output;
}

TEST(AppConfig, NestedTablesAreCheckedToo) {
  const auto path = writeConfig("nested", "[sinks.y4m]\nenabled = true\npaht = \"x.y4m\"\n");
  const auto r = run("--check-config --config " + path);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find(path + ":3: sinks.y4m.paht: unknown key"), std::string::npos) << r.output;
}

TEST(AppConfig, SetValuesAreLocatedOnTheCommandLine) {
  const auto r = run("--check-config --config " FIELDCAST_SOURCE_DIR "/config/fieldcast.toml --set render.fov_deg=500");
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("--set: render.fov_deg: expected a number from 5 to 150, got 500"), std::string::npos)
      << r.output;
}

// The field clock needs 1 ms for a field's work and a wake-up within the field's own period: a lead
// outside that is refused by --check-config, naming the key, not when the field thread starts.
TEST(AppConfig, TheLeadLeavesTheFieldClockItsRoom) {
  const std::string shipped = "--check-config --config " FIELDCAST_SOURCE_DIR "/config/fieldcast.toml";
  const auto tooShort = run(shipped + " --set warp.lead_ms=0.9");
  EXPECT_EQ(tooShort.exitCode, 1) << tooShort.output;
  EXPECT_NE(tooShort.output.find("warp.lead_ms"), std::string::npos) << tooShort.output;
  const auto tooLong = run(shipped + " --set warp.lead_ms=17");
  EXPECT_EQ(tooLong.exitCode, 1) << tooLong.output;
  EXPECT_NE(tooLong.output.find("warp.lead_ms: expected less than one field period (16.68 ms at 59.94 Hz), got 17"),
            std::string::npos)
      << tooLong.output;
  EXPECT_EQ(run(shipped + " --set warp.lead_ms=16.5").exitCode, 0);
  EXPECT_EQ(run(shipped + " --set output.rate=50 --set warp.lead_ms=17").exitCode, 0);
}

TEST(AppConfig, MirrorIsOneOfFourWords) {
  const std::string shipped = "--check-config --config " FIELDCAST_SOURCE_DIR "/config/fieldcast.toml";
  const auto horizontal = run(shipped + " --set warp.mirror=horizontal");
  EXPECT_EQ(horizontal.exitCode, 0) << horizontal.output;
  EXPECT_NE(horizontal.output.find("uyvy422 mirrored left-right;"), std::string::npos) << horizontal.output;
  const auto sideways = run(shipped + " --set warp.mirror=sideways");
  EXPECT_EQ(sideways.exitCode, 1);
  EXPECT_NE(sideways.output.find("warp.mirror"), std::string::npos) << sideways.output;
}

TEST(AppConfig, ViewTakesAWindowAndAStereoEye) {
  const std::string shipped = "--check-config --config " FIELDCAST_SOURCE_DIR "/config/fieldcast.toml";
  const auto offAxis = run(shipped +
                           " --set 'view.frustum_deg=[10, 50, 20, -12]' --set view.eye=left "
                           "--set view.eye_separation_m=0.065 --set view.convergence_m=3");
  EXPECT_EQ(offAxis.exitCode, 0) << offAxis.output;
  // (a window 40° wide and 32° high on a 720 × 486 image: pixels narrower than high, and said so)
  EXPECT_NE(offAxis.output.find("frustum 10.000/50.000/20.000/-12.000 deg (pixels 0.841 wide for 1 high), left eye "
                                "0.065 m apart, converging at 3.000 m"),
            std::string::npos)
      << offAxis.output;
  const auto parallel = run(shipped + " --set view.eye=right");
  EXPECT_NE(parallel.output.find("fov 60.000 deg, right eye 0.064 m apart, axes parallel"), std::string::npos)
      << parallel.output;
  for (const char* bad : {"[20, 10, 20, -12]", "[-85, 30, 20, -12]", "[-30, 30, -5, 5]", "[-30, 30, 20]"}) {
    const auto r = run(shipped + " --set 'view.frustum_deg=" + bad + "'");
    EXPECT_EQ(r.exitCode, 1) << bad << ": " << r.output;
    EXPECT_NE(r.output.find("view.frustum_deg"), std::string::npos) << r.output;
  }
  // An eye converging so near that its shifted window reaches 80° from its axis
  const auto crossEyed = run(shipped +
                             " --set render.fov_deg=150 --set view.eye=left --set view.eye_separation_m=0.4 "
                             "--set view.convergence_m=0.1");
  EXPECT_EQ(crossEyed.exitCode, 1) << crossEyed.output;
  EXPECT_NE(crossEyed.output.find("view.convergence_m: the eye's window"), std::string::npos) << crossEyed.output;
  const auto cyclops = run(shipped + " --set view.eye=middle");
  EXPECT_EQ(cyclops.exitCode, 1);
  EXPECT_NE(cyclops.output.find("view.eye"), std::string::npos) << cyclops.output;
}

TEST(AppConfig, LockTakesThisChannelsAddressAndItsPeers) {
  const std::string shipped = "--check-config --config " FIELDCAST_SOURCE_DIR "/config/fieldcast.toml";
  const auto locked = run(
      shipped + " --set 'lock.listen=\"127.0.0.1:7301\"' --set 'lock.peers=[\"127.0.0.1:7302\", \"127.0.0.1:7303\"]'");
  EXPECT_EQ(locked.exitCode, 0) << locked.output;
  EXPECT_NE(locked.output.find("frame lock on 127.0.0.1:7301 with 2 peers"), std::string::npos) << locked.output;
  const std::pair<const char*, const char*> bad[] = {
      {" --set 'lock.listen=\"localhost:7301\"'", "lock.listen: expected \"address:port\""},
      {" --set 'lock.listen=\"127.0.0.1:7301\"' --set 'lock.peers=[\"127.0.0.1\"]'", "lock.peers: expected"},
      {" --set 'lock.peers=[\"127.0.0.1:7302\"]'", "lock.listen: the lock needs this channel's own address"},
      {" --set 'lock.listen=\"127.0.0.1:7301\"' --set 'lock.peers=[\"127.0.0.1:7301\"]'",
       "lock.peers: this channel's own address"},
      {" --set 'lock.listen=\"127.0.0.1:7301\"' --set 'lock.peers=[\"127.0.0.1:0\"]'",
       "lock.peers: a peer's port cannot be 0"},
      {" --set 'lock.listen=\"127.0.0.1:7301\"' --set 'input.sync=\"gpiochip0:17\"'",
       "lock.listen: a channel locks to the GPIO sync input (input.sync) or to the other channels, not both"}};
  for (const auto& [set, message] : bad) {
    const auto r = run(shipped + set);
    EXPECT_EQ(r.exitCode, 1) << set << ": " << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
  }
}

TEST(AppConfig, MalformedSetIsAnError) {
  const auto r = run("--check-config --config " FIELDCAST_SOURCE_DIR "/config/fieldcast.toml --set novalue");
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("expected table.key=value"), std::string::npos) << r.output;
}

}  // namespace
