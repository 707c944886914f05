#!/usr/bin/env bash
# The stick's freeze button end to end: a replayed stick presses button 2 three seconds in. With a
# profile mapping it to freeze, the last second of video is one still picture while the fields keep
# coming; with the generic profile (button unmapped) the same run keeps flying.
# Usage: cockpit_freeze_test.sh <fieldcast> <data dir> <work dir>
set -euo pipefail
fieldcast=$1 data=$2 work=$3
mkdir -p "$work"

# Distinct pictures among the last 30 frames of a Y4M file of 180 equal frames (6 s).
distinct_last_frames() {
  local file=$1 header size frame count=180
  header=$(head -n 1 "$file")
  size=$(($(stat -c %s "$file") - ${#header} - 1))
  frame=$((size / count))
  if ((frame == 0 || frame * count != size)); then
    echo "$file: $size bytes of frames is not 180 frames (6 s of video)" >&2
    return 1
  fi
  for ((k = count - 30; k < count; ++k)); do
    tail -c +$((${#header} + 1 + k * frame + 1)) "$file" | head -c "$frame" | md5sum
  done | sort -u | wc -l
}

run() {  # run <name> [extra --set ...]
  local name=$1
  shift
  "$fieldcast" --duration 6 --set motion.source=stick \
    --set "input.stick=replay:$data/cockpit_freeze.rec:realtime" "$@" \
    --y4m "$work/$name.y4m" --summary "$work/$name.json" >"$work/$name.log" 2>&1 || {
    cat "$work/$name.log" >&2
    return 1
  }
}

run frozen --set "input.profile=$data/cockpit_freeze.toml"
grep -q '"freezes": 1' "$work/frozen.json" || { echo "frozen run: the summary counts no freeze" >&2; exit 1; }
frozen=$(distinct_last_frames "$work/frozen.y4m")
if ((frozen != 1)); then
  echo "button 2 mapped to freeze: $frozen distinct pictures in the last 30 frames, expected 1" >&2
  exit 1
fi

run flying
flying=$(distinct_last_frames "$work/flying.y4m")
# Flying, nearly every frame is a new picture; a stall of the machine in the last second makes the
# Y4M sink repeat the frames it cost (a 100 ms stall: three), so "many" is at least 20 of 30.
if ((flying < 20)); then
  echo "button 2 unmapped: only $flying distinct pictures in the last 30 frames, the flight should go on" >&2
  exit 1
fi
echo "freeze held: 1 picture over the last 30 frames (unmapped: $flying)"
