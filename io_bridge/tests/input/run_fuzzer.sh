#!/bin/sh
# Runs a libFuzzer target briefly (CTest label "fuzz"); exit 77 = skipped, with the reason.
# Usage: run_fuzzer.sh <fuzzer-binary> <corpus-dir> <reason-if-missing> [libFuzzer flags...]
fuzzer=$1
corpus=$2
reason=$3
shift 3
if [ ! -x "$fuzzer" ]; then
  echo "SKIPPED: $reason"
  exit 77
fi
mkdir -p "$corpus"
exec "$fuzzer" "$@" "$corpus"
