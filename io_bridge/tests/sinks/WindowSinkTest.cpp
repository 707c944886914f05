#include <io_bridge/SinkHub.h>
#include <io_bridge/WindowSink.h>

#include "TestFields.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <thread>

namespace fieldcast::io {
namespace {

using testing::makeField;
using testing::testFormat;

// Sets an environment variable for the scope of a test.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : mName(name) {
    if (const char* old = std::getenv(name)) mOld = old;
    if (value) {
      setenv(name, value, 1);
    } else {
      unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (mOld) {
      setenv(mName, mOld->c_str(), 1);
    } else {
      unsetenv(mName);
    }
  }

 private:
  const char* mName;
  std::optional<std::string> mOld;
};

TEST(WindowKeys, DecodeQtAndGtkCodes) {
  EXPECT_EQ(decodeWindowKey(0x01000012), WindowKey::Left);
  EXPECT_EQ(decodeWindowKey(65363), WindowKey::Right);
  EXPECT_EQ(decodeWindowKey('w'), WindowKey::Up);
  EXPECT_EQ(decodeWindowKey('+'), WindowKey::Faster);
  EXPECT_EQ(decodeWindowKey(27), WindowKey::Quit);
  EXPECT_EQ(decodeWindowKey('x'), WindowKey::Other);
}

TEST(WindowSinkNoDisplay, FailsWithAClearMessageNotACrash) {
  ScopedEnv platform("QT_QPA_PLATFORM", nullptr);
  {
    ScopedEnv display("DISPLAY", nullptr);
    WindowSink sink({});
    try {
      sink.open(testFormat(64, 16));
      FAIL() << "open() should refuse without a display";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("DISPLAY is not set"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("xvfb-run"), std::string::npos) << e.what();
    }
  }
  {
    ScopedEnv display("DISPLAY", ":93");  // no X server there
    EXPECT_EQ(WindowSink::displayProblem(), "cannot connect to X display :93");
  }
}

TEST(WindowSinkNoDisplay, TheHubRefusesToStartAndSaysWhy) {
  ScopedEnv platform("QT_QPA_PLATFORM", nullptr);
  ScopedEnv display("DISPLAY", nullptr);
  SinkHub hub(testFormat(64, 16));
  hub.add(std::make_unique<WindowSink>(WindowSinkOptions{}));
  try {
    hub.start();
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("sink 'window': sinks.window: DISPLAY is not set"), std::string::npos)
        << e.what();
  }
}

// Runs for real under a display; the CTest entry io_sinks_window_under_xvfb runs it in xvfb-run.
TEST(WindowSinkDisplay, ShowsInterlacedFieldsWithOverlay) {
  const std::string problem = WindowSink::displayProblem();
  if (!problem.empty()) GTEST_SKIP() << problem << " (CTest runs this again under xvfb-run when it is installed)";
  const StreamFormat f = testFormat(720, 486);
  WindowSink sink({"Fieldcast test", true, [](int, WindowKey) {}});
  sink.open(f);
  sink.setFigures({59.9, 120, 1, 42});
  for (std::uint64_t k = 0; k < 12; ++k) ASSERT_EQ(sink.consume(makeField(f, k)), SinkStatus::Ok) << sink.endReason();
  EXPECT_EQ(sink.fieldsShown(), 12u);
  sink.close();
}

}  // namespace
}  // namespace fieldcast::io

namespace fieldcast::io {
namespace {

// The service runs the window on a SinkHub worker thread, not on main().
TEST(WindowSinkDisplay, RunsOnAHubWorker) {
  const std::string problem = WindowSink::displayProblem();
  if (!problem.empty()) GTEST_SKIP() << problem << " (CTest runs this again under xvfb-run when it is installed)";
  const StreamFormat f = testing::testFormat(720, 486);
  SinkHub hub(f);
  hub.add(std::make_unique<WindowSink>(WindowSinkOptions{}));
  hub.start();
  for (std::uint64_t k = 0; k < 30; ++k) {
    hub.publish(testing::makeField(f, k));
    std::this_thread::sleep_for(std::chrono::milliseconds(16));
  }
  hub.stop();
  const auto figures = hub.figures()[0];
  EXPECT_FALSE(figures.ended) << figures.endReason;
  EXPECT_EQ(figures.consumed + figures.droppedFull, 30u);
  EXPECT_GT(figures.consumed, 20u);
}

}  // namespace
}  // namespace fieldcast::io
