#!/usr/bin/env bash
# scripts/rig.sh as the README runs it, made small: three channels of 240×162 for 6 s over a
# 1 km built-in terrain, driven by fieldcast-host. rig.sh ends with fieldcast-rig --check; this
# also asks that the host heard every channel's Start of Frames.
#   run_rig_test.sh SOURCE_DIR BUILD_DIR WORK_DIR
set -euo pipefail
src=$1
build=$2
work=$3
rm -rf "$work"
mkdir -p "$work/cache"
cat > "$work/rig.toml" <<TOML
[terrain]
source = "builtin"
cache_dir = "$work/cache"
builtin_size = 512
memory_budget_mb = 64
[render]
fov_deg = 60
[threads]
realtime_field_thread = false
realtime_host_thread = false
TOML
cat > "$work/flight.toml" <<'TOML'
name = "rig test pass"
camera_pitch_deg = -10
[[waypoint]]
t = 0
position = [200.0, 150.0, 320.0]
[[waypoint]]
t = 8
position = [260.0, 850.0, 330.0]
TOML
# A shared machine (the other tests run beside this one) may cost a channel a few fields
"$src/scripts/rig.sh" --no-setup --build-dir "$build" --config "$work/rig.toml" --flight "$work/flight.toml" \
  --duration 6 --size 240x162 --out "$work/out" --base-port 18404 --allow-missed 6
for channel in 2 3; do
  if ! grep -Eq "start of frames from channel $channel: [1-9][0-9]+" "$work/out/host.txt"; then
    echo "run_rig_test: the host heard no Start of Frames from channel $channel" >&2
    cat "$work/out/host.txt" >&2
    exit 1
  fi
done
# Channels locked to one epoch report the same frame numbers in their Start of Frames
if ! grep -Eq "frame numbers reported by the measured channel and another: [1-9][0-9]{2,}," "$work/out/host.txt"; then
  echo "run_rig_test: the channels' Start of Frames do not share frame numbers" >&2
  cat "$work/out/host.txt" >&2
  exit 1
fi
echo "run_rig_test: passed"
