#!/usr/bin/env bash
# Runs a libFuzzer binary briefly over a scratch corpus seeded from ig_core/fuzz/corpus.
# Usage: run_fuzzer.sh <fuzzer binary> <scratch corpus dir> <skip reason or ""> [libFuzzer args...]
# Exits 77 (CTest: skipped) with the reason when the fuzzer was not built.
set -euo pipefail
binary=$1 corpus=$2 reason=$3
shift 3
if [[ -n "$reason" || ! -x "$binary" ]]; then
  echo "[  SKIPPED ] ${reason:-fuzzer $binary not built}"
  exit 77
fi
mkdir -p "$corpus"
cp -n "$(dirname "$0")"/corpus/* "$corpus"/ 2>/dev/null || true
exec "$binary" "$corpus" "$@"
