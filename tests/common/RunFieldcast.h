#pragma once
// Runs the built executables (`fieldcast`: FIELDCAST_EXE) as a user would, for integration tests.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace fieldcast::testing {

struct RunResult {
  int exitCode = -1;   ///< -1 when it did not exit normally (killed by the timeout, say)
  std::string output;  ///< stdout and stderr together
};

/// Runs `<executable> <args>` through the shell. Every run is bounded by coreutils' timeout, so a
/// hang fails the test that caused it instead of stalling the suite.
inline RunResult runProgram(const std::string& executable, const std::string& args, int timeoutS = 120) {
  const std::string command = "timeout -s KILL " + std::to_string(timeoutS) + " " + executable + " " + args + " 2>&1";
  RunResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe)) result.output += buffer.data();
  const int status = pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

/// Runs `fieldcast <args>` (FIELDCAST_EXE), as runProgram does.
inline RunResult runFieldcast(const std::string& args, int timeoutS = 120) {
  return runProgram(FIELDCAST_EXE, args, timeoutS);
}

}  // namespace fieldcast::testing
