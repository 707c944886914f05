#!/usr/bin/env bash
# fieldcast-stall-probe sees a stall: the probe's process is stopped (SIGSTOP) for 150 ms, which
# no thread of it can run through, so every CPU's probe must record one wake-up at least 100 ms
# late; SIGTERM then ends it and it writes its file. Skipped (77) where the probe cannot have a
# real-time thread on every CPU (it then writes nothing, by design).
#   run_stall_probe_test.sh BUILD_DIR WORK_DIR
set -euo pipefail
build=$1
work=$2
rm -rf "$work"
mkdir -p "$work"
"$build/tools/rig/fieldcast-stall-probe" --out "$work/stalls.csv" > "$work/probe.txt" 2> "$work/probe.err" &
probe=$!
# Its threads running: the main thread, the one that joins the probes, one probe per CPU
for _ in $(seq 100); do
  [[ $(ls "/proc/$probe/task" 2>/dev/null | wc -l) -ge $(($(nproc) + 2)) ]] && break
  sleep 0.1
done
sleep 0.2
kill -STOP "$probe"
sleep 0.15
kill -CONT "$probe"
sleep 0.3
kill -TERM "$probe"
status=0
wait "$probe" || status=$?
cat "$work/probe.txt" "$work/probe.err"
if [[ $status -ne 0 ]]; then
  if grep -q "not a real-time thread pinned to every CPU" "$work/probe.err"; then
    echo "run_stall_probe_test: skipped: no real-time thread here (needs root or CAP_SYS_NICE)"
    exit 77
  fi
  echo "run_stall_probe_test: the probe failed ($status)" >&2
  exit 1
fi
cat "$work/stalls.csv"
cpus=$(grep -c '^cpu [0-9]*:' "$work/probe.txt")
# CPUs with a stall of 100 ms or more (woke_ns − due_ns)
stalled=$(awk -F, 'NR > 1 && $3 - $2 >= 100e6 && !($1 in seen) { seen[$1] = 1; n++ } END { print n + 0 }' \
  "$work/stalls.csv")
if [[ $cpus -lt 1 || $stalled -ne $cpus ]]; then
  echo "run_stall_probe_test: $stalled of $cpus CPUs recorded the 150 ms stop" >&2
  exit 1
fi
echo "run_stall_probe_test: passed ($cpus CPUs saw the stop)"
