#include <fieldcast/ConfigReader.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>

namespace fieldcast {
namespace {

std::string errorOf(const std::function<void()>& read) {
  try {
    read();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ConfigReader, ReadsTypedValuesWithDefaults) {
  ConfigReader r =
      ConfigDocument::parseText("n = 2.5\ni = 7\nb = true\ns = \"word\"\nv = [1, 2, 3]\n", "a.toml").root();
  EXPECT_EQ(r.number("n", 0.0, 0.0, 10.0), 2.5);
  EXPECT_EQ(r.integer("i", 0, 0, 10), 7);
  EXPECT_TRUE(r.boolean("b", false));
  EXPECT_EQ(r.string("s", ""), "word");
  EXPECT_EQ(r.numbers("v", {}, 3), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(r.number("absent", 4.0, 0.0, 10.0), 4.0);
  EXPECT_FALSE(r.optionalInteger("absent", 0, 1).has_value());
  EXPECT_NO_THROW(r.finish());
}

TEST(ConfigReader, OutOfRangeNamesFileLineKeyAndValue) {
  ConfigReader r = ConfigDocument::parseText("[t]\nx = 1\nq = 20\n", "cfg.toml").root();
  ConfigReader t = r.table("t");
  EXPECT_EQ(errorOf([&] { t.number("q", 1.0, 0.25, 16.0); }),
            "cfg.toml:3: t.q: expected a number from 0.25 to 16, got 20");
  EXPECT_EQ(errorOf([&] { t.integer("x", 0, 2, 5); }), "cfg.toml:2: t.x: expected an integer from 2 to 5, got 1");
  EXPECT_EQ(errorOf([&] { t.boolean("x", false); }), "cfg.toml:2: t.x: expected true or false, got 1");
}

TEST(ConfigReader, UnknownKeyIsRejectedAndTheKnownOnesListed) {
  ConfigReader r = ConfigDocument::parseText("[t]\nrate = 50\nrat = 50\n", "cfg.toml").root();
  ConfigReader t = r.table("t");
  t.number("rate", 0, 0, 100);
  EXPECT_EQ(errorOf([&] { t.finish(); }), "cfg.toml:3: t.rat: unknown key (expected one of: rate)");
  // The top table knows "t" was read: only its own unread keys count.
  EXPECT_NO_THROW(r.finish());
}

TEST(ConfigReader, ChoiceListsTheWords) {
  enum class Kind { A, B };
  ConfigReader r = ConfigDocument::parseText("k = \"c\"\nn = 3\n", "cfg.toml").root();
  EXPECT_EQ(errorOf([&] {
              r.choice("k", Kind::A, {{"a", Kind::A}, {"b", Kind::B}});
            }),
            "cfg.toml:1: k: expected one of \"a\", \"b\", got \"c\"");
  EXPECT_EQ(errorOf([&] { r.choice("n", Kind::A, {{"a", Kind::A}}); }), "cfg.toml:2: n: expected one of \"a\", got 3");
  EXPECT_EQ(r.choice("absent", Kind::B, {{"a", Kind::A}}), Kind::B);
}

TEST(ConfigReader, FailWithoutTheKeyPointsAtTheTable) {
  ConfigReader r = ConfigDocument::parseText("x = 1\n\n[t]\ny = 2\n", "cfg.toml").root();
  ConfigReader t = r.table("t");
  EXPECT_EQ(errorOf([&] { t.fail("z", "z is required"); }), "cfg.toml:3: t.z: z is required");
  EXPECT_EQ(errorOf([&] { t.fail("y", "expected an odd number"); }), "cfg.toml:4: t.y: expected an odd number, got 2");
}

TEST(ConfigReader, ArraysOfTablesAreNumberedFromOne) {
  ConfigReader r = ConfigDocument::parseText("[[w]]\nt = 1\n[[w]]\nt = 2\nu = 3\n", "f.toml").root();
  std::vector<ConfigReader> w = r.tables("w");
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0].number("t", 0, 0, 10), 1.0);
  EXPECT_NO_THROW(w[0].finish());
  w[1].number("t", 0, 0, 10);
  EXPECT_EQ(errorOf([&] { w[1].finish(); }), "f.toml:5: w[2].u: unknown key (expected one of: t)");
  EXPECT_TRUE(r.tables("absent").empty());
}

TEST(ConfigReader, StringsAndIntegerLists) {
  ConfigReader r =
      ConfigDocument::parseText("one = \"x\"\nmany = [\"a\", \"b\"]\nbad = [1]\nn = [1, 70000]\n", "f.toml").root();
  EXPECT_EQ(r.strings("one"), (std::vector<std::string>{"x"}));
  EXPECT_EQ(r.strings("many"), (std::vector<std::string>{"a", "b"}));
  EXPECT_FALSE(r.strings("absent").has_value());
  EXPECT_EQ(errorOf([&] { r.strings("bad"); }), "f.toml:3: bad: expected a string or an array of strings, got 1");
  EXPECT_EQ(errorOf([&] { r.integers("n", 1, 0xFFFF, 8); }),
            "f.toml:4: n: expected an array of at most 8 integers from 1 to 65535, got 70000");
}

TEST(ConfigReader, RelativePathsAreRelativeToTheFileAndSetValuesToTheCurrentFolder) {
  const std::string dir = testing::TempDir() + "config_reader_paths";
  std::filesystem::create_directories(dir);
  const std::string file = dir + "/c.toml";
  std::ofstream(file) << "[t]\np = \"sub/x.y4m\"\nabs = \"/a/b\"\n";
  ConfigReader t = ConfigDocument::parseFile(file, {"t.q=other.png"}).root().table("t");
  EXPECT_EQ(t.path("p", ""), std::filesystem::path(dir) / "sub/x.y4m");
  EXPECT_EQ(t.path("abs", ""), std::filesystem::path("/a/b"));
  EXPECT_EQ(t.path("q", ""), std::filesystem::path("other.png"));  // from --set: as given
  EXPECT_EQ(t.path("absent", ""), std::filesystem::path());
}

TEST(ConfigReader, SetOverridesCreateTablesAndAreLocatedOnTheCommandLine) {
  const std::string file = testing::TempDir() + "config_reader_set.toml";
  std::ofstream(file) << "[output]\nrate = 59.94\n";
  ConfigReader root = ConfigDocument::parseFile(file, {"output.rate=50", "sinks.y4m.enabled=true"}).root();
  EXPECT_EQ(root.table("output").number("rate", 0, 0, 100), 50.0);
  EXPECT_TRUE(root.table("sinks").table("y4m").boolean("enabled", false));
  ConfigReader bad = ConfigDocument::parseFile(file, {"output.rate=500"}).root().table("output");
  EXPECT_EQ(errorOf([&] { bad.number("rate", 0, 0, 100); }),
            "--set: output.rate: expected a number from 0 to 100, got 500");
  EXPECT_NE(errorOf([&] { ConfigDocument::parseFile(file, {"novalue"}); }).find("expected table.key=value"),
            std::string::npos);
}

TEST(ConfigReader, SyntaxErrorNamesFileAndLine) {
  EXPECT_EQ(errorOf([] { ConfigDocument::parseText("a = 1\nb = = 2\n", "s.toml"); }).rfind("s.toml:2: ", 0), 0u);
}

TEST(ConfigReader, ReaderOutlivesItsDocument) {
  // Readers keep the document alive: a module may keep a reader after the document goes out of scope.
  ConfigReader t = ConfigDocument::parseText("[t]\nx = 3\n", "k.toml").root().table("t");
  EXPECT_EQ(t.integer("x", 0, 0, 5), 3);
}

}  // namespace
}  // namespace fieldcast
