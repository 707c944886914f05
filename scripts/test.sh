#!/usr/bin/env bash
# Builds Fieldcast and runs every test: the Release build with all labels but `soak`, then the
# unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer, then the lock-free
# hand-offs' concurrency tests under ThreadSanitizer.
# Installs what it needs first; safe to run any number of times.
#   scripts/test.sh             everything
#   scripts/test.sh --fast      Release build and tests only (no sanitizer passes)
#   scripts/test.sh --soak      the long soak runs (label soak) only
set -euo pipefail
cd "$(dirname "$0")/.."

mode="${1:-all}"
jobs=$(nproc)

scripts/install-deps.sh --interop

build() {  # build <dir> [cmake args...]
  local dir=$1; shift
  cmake -S . -B "$dir" -G Ninja "$@" >/dev/null
  cmake --build "$dir" -j "$jobs"
}

if [[ "$mode" == "--soak" ]]; then
  build build
  ctest --test-dir build -L soak --output-on-failure --verbose | grep -E "^[0-9]+: soak|tests passed|Failed|Passed"
  exit 0
fi

echo "== Release build and tests"
build build -DCMAKE_BUILD_TYPE=Release
ctest --test-dir build -LE soak -j "$jobs" --output-on-failure --timeout 900

if [[ "$mode" != "--fast" ]]; then
  echo "== AddressSanitizer + UndefinedBehaviorSanitizer build, unit tests"
  build build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIELDCAST_SANITIZE=address,undefined -DFIELDCAST_BUILD_BENCH=OFF
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan -L unit -j "$jobs" --output-on-failure --timeout 900

  echo "== ThreadSanitizer build, concurrency tests of the lock-free hand-offs"
  # Only the executables that hold them, and only those tests: TSan slows the rest 5-15x for nothing.
  cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIELDCAST_SANITIZE=thread \
    -DFIELDCAST_BUILD_BENCH=OFF -DFIELDCAST_FUZZ=OFF >/dev/null
  cmake --build build-tsan -j "$jobs" --target fieldcast_types_tests fieldcast_terrain_tests fieldcast_warp_tests \
    fieldcast_render_tests fieldcast_motion_tests fieldcast_service_tests fieldcast_io_lock_tests fieldcast_io_sinks_tests
  TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 \
    ctest --test-dir build-tsan -j "$jobs" --output-on-failure --timeout 900 \
      -R '^(SeqLock|TileCacheTest|TripleBuffer|RenderPool|FlightModel|HostMotion|DurationHistogram|FieldLockLink|SinkHub)\.'
fi
