#!/usr/bin/env bash
# Runs every libFuzzer target of a build for longer than the short `ctest -L fuzz` runs, each over
# its scratch corpus and its seed corpus, and prints the executions and crashes per target.
#   scripts/fuzz.sh                       every target until 10,000,000 executions (or 1 h each)
#   scripts/fuzz.sh --runs N --time S     stop each target at N executions or S seconds
#   scripts/fuzz.sh --build DIR           use the fuzzers of build directory DIR (default: build)
#   scripts/fuzz.sh --only NAME           one target (its name contains NAME)
# The targets, their corpora and their libFuzzer options are read from CTest (label fuzz), so a
# target added with fieldcast_add_fuzzer is run here without editing this script. Crash inputs are
# written to <build>/fuzz-artifacts/<target>/. Exits 1 when any target crashed or could not run.
set -euo pipefail
cd "$(dirname "$0")/.."

runs=10000000 seconds=3600 build=build only=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --runs) runs=$2; shift 2 ;;
    --time) seconds=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --only) only=$2; shift 2 ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "fuzz.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: --runs must be a positive integer, got '$runs'" >&2; exit 2; }
[[ "$seconds" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: --time must be a positive integer of seconds, got '$seconds'" >&2; exit 2; }
[[ -f "$build/CTestTestfile.cmake" ]] || { echo "fuzz.sh: '$build' is not a configured build directory (run scripts/test.sh first)" >&2; exit 2; }

# One line per target: name, binary, scratch corpus, then seed directories and options, tab-separated.
targets=$(ctest --test-dir "$build" -L fuzz --show-only=json-v1 | python3 -c '
import json, sys
for test in json.load(sys.stdin)["tests"]:
    command = test["command"]  # run_fuzzer.sh <binary> <corpus> <skip reason> [seeds and options]
    print("\t".join([test["name"], command[1], command[2]] + command[4:]))
')

status=0
printf '%-42s %14s %9s %12s %8s\n' target executions seconds "execs/s" crashes
while IFS=$'\t' read -r -a row; do
  name=${row[0]} binary=${row[1]} corpus=${row[2]}
  [[ -z "$only" || "$name" == *"$only"* ]] || continue
  if [[ ! -x "$binary" ]]; then
    printf '%-42s %s\n' "$name" "not built (configure with -DFIELDCAST_FUZZ=ON and install clang: scripts/install-deps.sh --interop)"
    status=1; continue
  fi
  seeds=() options=()
  for argument in "${row[@]:3}"; do
    case "$argument" in
      -runs=*|-max_total_time=*) ;;  # replaced by this script's limits
      -*) options+=("$argument") ;;
      *) seeds+=("$argument") ;;
    esac
  done
  artifacts="$build/fuzz-artifacts/${name##*.}"
  log="$build/fuzz-artifacts/${name##*.}.log"
  mkdir -p "$corpus" "$artifacts"
  touch "$artifacts/.started"  # crash inputs of earlier runs stay, but are not counted again
  started=$(date +%s.%N)
  set +e
  "$binary" "$corpus" "${seeds[@]}" "${options[@]}" -runs="$runs" -max_total_time="$seconds" \
    -artifact_prefix="$artifacts/" -print_final_stats=1 >"$log" 2>&1
  exit_code=$?
  set -e
  elapsed=$(python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.0f}')" "$started" "$(date +%s.%N)")
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  crashes=$(find "$artifacts" -maxdepth 1 -type f -newer "$artifacts/.started" \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | wc -l)
  [[ $exit_code -eq 0 ]] || { status=1; [[ $crashes -gt 0 ]] || crashes="exit $exit_code"; }
  rate=$(python3 -c "import sys; print(f'{int(sys.argv[1] or 0) / max(float(sys.argv[2]), 1):.0f}')" "${executions:-0}" "$elapsed")
  printf '%-42s %14s %9s %12s %8s\n' "$name" "${executions:-?}" "$elapsed" "$rate" "$crashes"
done <<<"$targets"
[[ $status -eq 0 ]] || echo "fuzz.sh: see the logs and crash inputs in $build/fuzz-artifacts/" >&2
exit $status
