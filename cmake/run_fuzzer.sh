#!/usr/bin/env bash
# Runs a libFuzzer binary briefly for CTest (label fuzz; registered by fieldcast_add_fuzzer in
# cmake/FieldcastFuzzing.cmake). New inputs go to a scratch corpus in the build tree; seed corpora
# are passed as further directories, which libFuzzer reads but never writes.
# Usage: run_fuzzer.sh <fuzzer binary> <scratch corpus dir> <skip reason or ""> [seed dirs and libFuzzer args...]
# Exits 77 (CTest: skipped) with the reason when the fuzzer was not built.
set -euo pipefail
binary=$1 corpus=$2 reason=$3
shift 3
if [[ -n "$reason" || ! -x "$binary" ]]; then
  echo "[  SKIPPED ] ${reason:-fuzzer $binary not built}"
  exit 77
fi
mkdir -p "$corpus"
exec "$binary" "$corpus" "$@"
