#!/usr/bin/env bash
# A three-channel rig on this machine: left, centre and right channels (60° each, edges
# abutting: 180° together), each a fieldcast process frame-locked to the others ([lock] on
# loopback), driven by one scripted CIGI host (fieldcast-host) flying the ridge run for 20 s.
# Writes into out/rig/:
#   out/rig/contact_sheet.png       the three channels' fields side by side, eight instants
#   out/rig/report.json             the lock figures (fieldcast-rig): display and emission spread
#   out/rig/<channel>/summary.json  each channel's run summary; fields.csv its per-field record
#   out/rig/host.json               what the host measured (Start of Frames from every channel)
#   out/rig/stalls.csv              when the machine itself stalled (fieldcast-stall-probe)
# Installs what is missing and builds first; safe to run any number of times. Options (for the
# test that runs it small): --config FILE (the channels' and the host's; the shipped one by
# default), --flight FILE, --duration S, --size WxH, --out DIR, --base-port N (host ports N to
# N+2, lock ports N+10 to N+12), --build-dir DIR, --no-setup (no install, no build),
# --allow-missed N. It fails when a channel missed a field while the host flew (more than N;
# fields a stall of the machine itself explains are reported apart), showed black or left the
# lock (fieldcast-rig --check).
set -euo pipefail
cd "$(dirname "$0")/.."

config=config/fieldcast.toml
flight=config/flights/ridge_run.toml
duration=20
size=720x486
out="$(pwd)/out/rig"
base_port=8004
build=build
setup=1
allow_missed=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --config) config=$2; shift 2 ;;
    --flight) flight=$2; shift 2 ;;
    --duration) duration=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --base-port) base_port=$2; shift 2 ;;
    --build-dir) build=$2; shift 2 ;;
    --no-setup) setup=0; shift ;;
    --allow-missed) allow_missed=$2; shift 2 ;;
    *) echo "rig.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
if [[ $setup == 1 ]]; then
  scripts/install-deps.sh
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j "$(nproc)" --target fieldcast fieldcast-host fieldcast-rig fieldcast-stall-probe
fi

rm -rf "$out"
mkdir -p "$out"
names=(left centre right)
yaws=(-60 0 60)
# The CPUs this script may use (a cpuset or taskset need not start at CPU 0)
cpus=()
IFS=, read -ra ranges <<< "$(awk '/^Cpus_allowed_list:/ { print $2 }' /proc/self/status)"
for range in "${ranges[@]}"; do
  for ((cpu = ${range%-*}; cpu <= ${range#*-}; cpu++)); do cpus+=("$cpu"); done
done
pids=()
probe=""
stop_channels() {
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" || true; done
  pids=()
}
stop_all() {
  stop_channels
  if [[ -n $probe ]]; then
    kill -TERM "$probe" 2>/dev/null || true
    wait "$probe" || true
  fi
}
trap stop_all EXIT
# The machine's own stalls over the run (a real-time thread pinned to each CPU, waking every
# millisecond): a field a stall of its field thread's CPU explains is reported apart
# (for an hour at most, should this script be killed before it can stop it)
"$build/tools/rig/fieldcast-stall-probe" --out "$out/stalls.csv" --duration 3600 > "$out/stall_probe.txt" 2>&1 &
probe=$!
# Waits until channel $1 (process $2) has emitted half a second of fields: it has its terrain,
# has joined the lock and runs. The first run builds the built-in terrain, hence the long wait.
wait_until_emitting() {
  local name=$1 pid=$2 deadline=$((SECONDS + 600)) lines
  while true; do
    lines=$({ wc -l < "$out/$name/fields.csv"; } 2>/dev/null || echo 0)
    [[ $lines -ge 31 ]] && return 0
    if ! kill -0 "$pid" 2>/dev/null; then
      echo "rig.sh: the $name channel stopped before it had emitted 30 fields; its log:" >&2
      tail -20 "$out/$name/log.txt" >&2
      exit 1
    fi
    if (( SECONDS >= deadline )); then
      echo "rig.sh: the $name channel had not emitted 30 fields after 600 s" >&2
      exit 1
    fi
    sleep 0.1
  done
}

for i in 0 1 2; do
  name=${names[$i]}
  mkdir -p "$out/$name/images"
  peers=()
  for j in 0 1 2; do [[ $j != "$i" ]] && peers+=("\"127.0.0.1:$((base_port + 10 + j))\""); done
  # Each channel renders at most 15 frames a second: three renderers and three field threads
  # share the machine's cores, and the field threads must never wait for a core. Each field
  # thread is pinned to a CPU in turn (so a stall of that CPU is what explains its misses) and
  # wakes 8 ms before its field's display time (4 ms alone on a machine): two field threads
  # share a CPU here and wake at one instant, the second starts when the first is done.
  "$build/app/fieldcast" --config "$config" \
    --set 'motion.source="host"' --set "host.port=$((base_port + i))" \
    --set "output.width=${size%x*}" --set "output.height=${size#*x}" \
    --set "view.offset_deg=[${yaws[$i]}, 0, 0]" --set render.threads=1 --set render.max_rate_hz=15 \
    --set warp.lead_ms=8 --set "threads.field_thread_cpu=${cpus[i % ${#cpus[@]}]}" \
    --set "lock.listen=\"127.0.0.1:$((base_port + 10 + i))\"" --set "lock.peers=[${peers[0]}, ${peers[1]}]" \
    --set sinks.y4m.enabled=false --set sinks.images.enabled=true \
    --set "sinks.images.directory=\"$out/$name/images\"" --set sinks.images.every_nth=150 \
    --field-log "$out/$name/fields.csv" --summary "$out/$name/summary.json" > "$out/$name/log.txt" 2>&1 &
  pids+=("$!")
  # One after the other, each running before the next starts: each joins the lock the first
  # began, and the first builds the terrain cache the others then read.
  wait_until_emitting "$name" "$!"
done
# The host flies once all three run: a channel loading its terrain can cost the running ones a
# field (two cores for three channels); fieldcast-rig reports those apart from the flight's.

"$build/tools/host/fieldcast-host" --config "$config" --flight "$flight" \
  --duration "$duration" --ig-port $((base_port + 1)) --also-ig-port "$base_port" --also-ig-port $((base_port + 2)) \
  --wait-for-ig 60 --summary "$out/host.json" | tee "$out/host.txt"
stop_channels
kill -TERM "$probe" 2>/dev/null || true  # it may have ended already: then it measured nothing
stalls=(--stalls "$out/stalls.csv")
if ! wait "$probe"; then
  stalls=()  # not measured: no field is excused
fi
probe=""
trap - EXIT
cat "$out/stall_probe.txt"

"$build/tools/rig/fieldcast-rig" --channel "left=$out/left" --channel "centre=$out/centre" \
  --channel "right=$out/right" --field-cpu "left=${cpus[0]}" --field-cpu "centre=${cpus[1 % ${#cpus[@]}]}" \
  --field-cpu "right=${cpus[2 % ${#cpus[@]}]}" --host "$out/host.json" "${stalls[@]}" \
  --sheet "$out/contact_sheet.png" --report "$out/report.json" --check --allow-missed "$allow_missed" |
  tee "$out/report.txt"

echo
echo "rig outputs:"
echo "  contact sheet  $out/contact_sheet.png"
echo "  lock figures   $out/report.json"
echo "  per channel    $out/{left,centre,right}/summary.json"
