#pragma once
// Runs a test's check at every SIMD level this build carries and this CPU runs
// (fieldcast/SimdLevel.h), so each vector kernel is judged at each level against its scalar
// reference; then puts the best level back. Header-only, for the unit tests of any module.

#include <fieldcast/SimdLevel.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

namespace fieldcast::testing {

/// Runs `check` once at every level, then puts the best level back.
template <typename Check>
void atEverySimdLevel(Check&& check) {
  const std::vector<std::string> levels = simdLevels();
  ASSERT_FALSE(levels.empty());
  for (const std::string& level : levels) {
    forceSimdLevel(level);
    ASSERT_EQ(dispatchedSimdLevel(), level) << "forcing did not reach the dispatch";
    ASSERT_EQ(simdLevel(), level);
    SCOPED_TRACE("SIMD level " + level);
    std::printf("checking at SIMD level %s\n", level.c_str());
    check();
  }
  forceSimdLevel("auto");
  EXPECT_EQ(simdLevel(), levels.front());
}

}  // namespace fieldcast::testing
