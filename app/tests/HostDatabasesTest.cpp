// Database switching on the host's request (IG Control's database number): what Start of Frame
// reports before, during and after a load, that the renderer is switched to the new database, that
// the one left behind is closed only once the renderer has let go of it, and that a HostSession
// answers from the new database after the switch. Two small built-in terrains of other seeds.

#include "HostDatabases.h"
#include "HostSession.h"

#include <ig_core/OpenTerrain.h>
#include <io_bridge/cigi/DatagramDecoder.h>

#include <gtest/gtest.h>

#include <unistd.h>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <thread>

namespace fieldcast::app {
namespace {

namespace cigi = io::cigi;
using namespace std::chrono_literals;

core::TerrainConfig builtinTerrain(const std::filesystem::path& cacheDir, std::uint64_t seed) {
  core::TerrainConfig c;
  c.cacheDir = cacheDir;
  c.builtin.sizeVox = 256;
  c.builtin.seed = seed;
  c.memoryBudgetBytes = std::size_t{64} << 20;
  return c;
}

class HostDatabasesTest : public ::testing::Test {
 protected:
  HostDatabasesTest()
      : mDir(std::filesystem::temp_directory_path() / ("fieldcast-host-databases-" + std::to_string(::getpid()))) {
    mFirst = core::openTerrain(builtinTerrain(mDir, 1));
    const core::TerrainGeometry& g = mFirst->geometry();
    for (int ty = 0; ty < g.tilesY(0); ++ty) {
      for (int tx = 0; tx < g.tilesX(0); ++tx) mFirst->request(0, tx, ty, -1.0);
    }
    EXPECT_TRUE(mFirst->waitIdle(10s));
    mInUse.store(mFirst.get());
  }
  ~HostDatabasesTest() override { std::filesystem::remove_all(mDir); }

  // Database 1 open, 2 (another seed) and 3 (a file that does not exist) known.
  std::unique_ptr<HostDatabases> makeDatabases() {
    HostDatabase second{2, builtinTerrain(mDir, 99)};
    HostDatabase missing{3, builtinTerrain(mDir, 1)};
    missing.terrain.database = mDir / "no-such-database.fctdb";
    OpenDatabase first{1, mFirst, std::make_shared<const core::Georeference>(core::Georeference::tangentPlane())};
    return std::make_unique<HostDatabases>(
        std::move(first), std::vector<HostDatabase>{second, missing}, core::kBuiltinTerrainOrigin,
        [this] { return mInUse.load(); }, [this](core::TileCache& terrain) { mSwitchedTo.store(&terrain); });
  }

  // Polls switchIfLoaded like the link thread does once per field, for up to 60 s.
  static std::optional<OpenDatabase> waitForSwitch(HostDatabases& databases) {
    for (int i = 0; i < 6000; ++i) {
      if (std::optional<OpenDatabase> loaded = databases.switchIfLoaded()) return loaded;
      std::this_thread::sleep_for(10ms);
    }
    return std::nullopt;
  }

  std::filesystem::path mDir;
  std::shared_ptr<core::TileCache> mFirst;
  std::atomic<const core::TileCache*> mInUse{nullptr};
  std::atomic<core::TileCache*> mSwitchedTo{nullptr};
};

TEST_F(HostDatabasesTest, StartOfFrameReportsTheLoadedTheLoadingAndTheUnavailableDatabase) {
  auto databases = makeDatabases();
  EXPECT_EQ(databases->startOfFrameNumber(), 1);
  databases->request(0);  // "no change"
  databases->request(1);  // the current one
  EXPECT_EQ(databases->startOfFrameNumber(), 1);
  databases->request(42);  // not configured
  EXPECT_EQ(databases->startOfFrameNumber(), HostDatabases::kNotAvailable);
  databases->request(1);  // the host gives up on it
  EXPECT_EQ(databases->startOfFrameNumber(), 1);

  databases->request(2);
  EXPECT_EQ(databases->startOfFrameNumber(), -2);  // loading: its negative, until the switch
  const std::optional<OpenDatabase> loaded = waitForSwitch(*databases);
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->number, 2);
  EXPECT_EQ(databases->startOfFrameNumber(), 2);
  EXPECT_EQ(databases->current().number, 2);
  EXPECT_EQ(databases->switches(), 1u);
  databases->request(2);  // the host goes on sending the number it asked for: nothing more happens
  EXPECT_EQ(databases->startOfFrameNumber(), 2);
  EXPECT_FALSE(databases->switchIfLoaded().has_value());
}

TEST_F(HostDatabasesTest, TheRendererIsSwitchedToTheNewDatabaseWhichIsAnotherTerrain) {
  auto databases = makeDatabases();
  databases->request(2);
  const std::optional<OpenDatabase> loaded = waitForSwitch(*databases);
  ASSERT_TRUE(loaded.has_value());
  ASSERT_EQ(mSwitchedTo.load(), loaded->terrain.get());
  // Another seed: the same places have other heights.
  int differ = 0;
  for (int i = 0; i < 50; ++i) {
    const double x = 20.0 + i * 9.0, y = 40.0 + i * 7.0;
    if (std::abs(loaded->terrain->heightAtM(x, y, 0) - mFirst->heightAtM(x, y, 0)) > 0.5) ++differ;
  }
  EXPECT_GT(differ, 25);
}

TEST_F(HostDatabasesTest, TheDatabaseLeftBehindIsClosedOnlyOnceTheRendererLetsGo) {
  auto databases = makeDatabases();
  const std::weak_ptr<core::TileCache> first = mFirst;
  mFirst.reset();  // the databases own it now
  databases->request(2);
  const std::optional<OpenDatabase> loaded = waitForSwitch(*databases);
  ASSERT_TRUE(loaded.has_value());
  std::this_thread::sleep_for(300ms);  // several of the loader's looks
  EXPECT_FALSE(first.expired()) << "closed while the renderer still had a frame of it in flight";
  mInUse.store(loaded->terrain.get());  // the renderer's newest frame is of the new database
  for (int i = 0; i < 500 && !first.expired(); ++i) std::this_thread::sleep_for(10ms);
  EXPECT_TRUE(first.expired());
}

TEST_F(HostDatabasesTest, ADatabaseThatCannotBeOpenedIsReportedUnavailableAndTheCurrentOneStays) {
  auto databases = makeDatabases();
  databases->request(3);
  for (int i = 0; i < 1000 && databases->failures() == 0; ++i) std::this_thread::sleep_for(10ms);
  EXPECT_EQ(databases->failures(), 1u);
  EXPECT_EQ(databases->startOfFrameNumber(), HostDatabases::kNotAvailable);
  EXPECT_FALSE(databases->switchIfLoaded().has_value());
  EXPECT_EQ(databases->current().number, 1);
  EXPECT_EQ(mSwitchedTo.load(), nullptr);
}

// The session end to end (no sockets): IG Control asks for database 2; Start of Frame says −2
// while it loads and 2 once a field has switched; heights are then answered from database 2.
TEST_F(HostDatabasesTest, TheSessionSwitchesBetweenFieldsAndAnswersFromTheNewDatabase) {
  auto databases = makeDatabases();
  VirtualClock clock{TimePoint{10s}};
  motion::HostMotion ownship;
  auto georeference = std::make_shared<const core::Georeference>(core::Georeference::tangentPlane());
  HostSession session(ownship, *mFirst, georeference, 1, clock);
  session.setDatabases(databases.get());

  std::uint64_t fieldNumber = 0;
  const auto field = [&] {
    cigi::IgMessageBuilder out;
    EXPECT_TRUE(session.onField(io::FieldAnnouncement{fieldNumber++, clock.now()}, out));
    cigi::IgDatagramDecoder decoder;
    std::vector<cigi::IgPacket> packets;
    EXPECT_TRUE(decoder.decode(out.bytes(), packets).accepted());
    return packets;
  };
  const auto databaseOf = [](const std::vector<cigi::IgPacket>& packets) {
    return std::get<cigi::StartOfFrame>(packets.front()).databaseNumber;
  };
  const glm::dvec3 pointM{151.0, 203.0, 900.0};
  const auto askHeight = [&](std::uint16_t id) {
    cigi::IgControl control;
    control.databaseNumber = 2;
    cigi::HatHotRequest request;
    request.hatHotId = id;
    request.requestType = cigi::HatHotRequestType::HeightOfTerrain;
    const auto geo = georeference->toGeodetic(pointM);
    request.latitudeDegOrXM = geo->latitudeDeg;
    request.longitudeDegOrYM = geo->longitudeDeg;
    request.altitudeMOrZM = geo->altitudeM;
    const std::vector<cigi::HostPacket> packets{control, request};
    session.onMessage(io::HostMessage{packets, clock.now(), false});
  };

  EXPECT_EQ(databaseOf(field()), 1);
  askHeight(1);
  std::vector<cigi::IgPacket> packets = field();
  EXPECT_EQ(databaseOf(packets), -2);
  std::vector<cigi::IgPacket> answers = packets;
  for (int i = 0; i < 6000 && databaseOf(packets) != 2; ++i) {
    std::this_thread::sleep_for(10ms);
    clock.advance(10ms);
    packets = field();
    answers.insert(answers.end(), packets.begin(), packets.end());
  }
  ASSERT_EQ(databaseOf(packets), 2);
  const std::shared_ptr<core::TileCache> second = databases->current().terrain;
  // The request made while database 1 rendered was answered from database 1.
  bool firstAnswered = false;
  for (const cigi::IgPacket& p : answers) {
    if (const auto* r = std::get_if<cigi::HatHotResponse>(&p); r != nullptr && r->hatHotId == 1) {
      EXPECT_NEAR(r->heightM, mFirst->heightAtM(pointM.x, pointM.y, 0), 0.05);
      firstAnswered = true;
    }
  }
  EXPECT_TRUE(firstAnswered);

  askHeight(2);
  bool secondAnswered = false;
  for (int i = 0; i < 200 && !secondAnswered; ++i) {
    std::this_thread::sleep_for(10ms);
    clock.advance(10ms);
    for (const cigi::IgPacket& p : field()) {
      if (const auto* r = std::get_if<cigi::HatHotResponse>(&p); r != nullptr && r->hatHotId == 2) {
        ASSERT_TRUE(r->valid);
        EXPECT_NEAR(r->heightM, second->heightAtM(pointM.x, pointM.y, 0), 0.05);
        EXPECT_GT(std::abs(r->heightM - mFirst->heightAtM(pointM.x, pointM.y, 0)), 0.5) << "the two seeds agree here";
        secondAnswered = true;
      }
    }
  }
  EXPECT_TRUE(secondAnswered);
}

}  // namespace
}  // namespace fieldcast::app
