#!/usr/bin/env bash
# fieldcast-stall-probe sees a stall: the probe's process is stopped (SIGSTOP) for 150 ms, which
# no thread of it can run through, so every CPU's probe must record one wake-up at least 100 ms
# late; SIGTERM then ends it and it writes its file.
#   run_stall_probe_test.sh BUILD_DIR WORK_DIR
set -euo pipefail
build=$1
work=$2
rm -rf "$work"
mkdir -p "$work"
"$build/tools/rig/fieldcast-stall-probe" --out "$work/stalls.csv" > "$work/probe.txt" &
probe=$!
sleep 0.5
kill -STOP "$probe"
sleep 0.15
kill -CONT "$probe"
sleep 0.3
kill -TERM "$probe"
wait "$probe"
cat "$work/probe.txt" "$work/stalls.csv"
cpus=$(grep -c '^cpu [0-9]*:' "$work/probe.txt")
# CPUs with a stall of 100 ms or more (woke_ns − due_ns)
stalled=$(awk -F, 'NR > 1 && $3 - $2 >= 100e6 { seen[$1] = 1 } END { print length(seen) }' "$work/stalls.csv")
if [[ $cpus -lt 1 || $stalled -ne $cpus ]]; then
  echo "run_stall_probe_test: $stalled of $cpus CPUs recorded the 150 ms stop" >&2
  exit 1
fi
echo "run_stall_probe_test: passed ($cpus CPUs saw the stop)"
