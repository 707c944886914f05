#pragma once
// The outer frame of every Fieldcast program: run it, and turn an exception that escapes into one
// "program: reason" line on stderr and exit status 1.

#include <cstdio>
#include <exception>

namespace fieldcast {

/// Returns run(argc, argv), or 1 after printing "name: reason" when it throws.
template <typename Run>
int runProgram(const char* name, Run&& run, int argc, char** argv) noexcept {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", name, e.what());
  } catch (...) {
    std::fprintf(stderr, "%s: fatal: unknown exception\n", name);
  }
  return 1;
}

}  // namespace fieldcast
