#!/usr/bin/env bash
# Compares the frame time of two or more builds of fieldcast-render on one of the render bench's
# views, on a noisy shared machine. The binaries take turns, ROUNDS times; each run is the median
# of 15 frames on one thread (THREADS=2 for two). The script prints each binary's medians sorted,
# the median of them, and its ratio to the first binary's. Alternating puts the machine's drift
# into every binary alike.
#
#   scripts/render-ab.sh VIEW ROUNDS BIN...     VIEW: down | oblique | low | horizon
#   scripts/render-ab.sh low 7 /tmp/before/fieldcast-render build/tools/render/fieldcast-render
#   THREADS=2 scripts/render-ab.sh horizon 9 /tmp/before/fieldcast-render build/tools/render/fieldcast-render
#
# Build the "before" binary from a worktree (git worktree add /tmp/wt REV, then cmake and ninja
# there). Also writes each binary's frame to /tmp/render-ab-<n>.png: compare them with cmp or idiff.
set -euo pipefail

usage() {
  echo "usage: $0 down|oblique|low|horizon ROUNDS BIN..." >&2
  exit 2
}
[[ $# -ge 3 ]] || usage
view=$1
rounds=$2
shift 2
# The views of fieldcast_bench_render: altitude above the terrain (m), heading, pitch (degrees).
case "$view" in
  down) pose="400,30,-70" ;;
  oblique) pose="250,75,-25" ;;
  low) pose="60,200,-8" ;;
  horizon) pose="30,315,-1" ;;
  *) usage ;;
esac
[[ "$rounds" =~ ^[1-9][0-9]*$ ]] || usage
threads=${THREADS:-1}
[[ "$threads" =~ ^[1-9][0-9]*$ ]] || usage
for bin in "$@"; do
  [[ -x "$bin" ]] || { echo "$0: $bin is not an executable" >&2; exit 2; }
done

declare -a times
for ((r = 0; r < rounds; r++)); do
  n=0
  for bin in "$@"; do
    ms=$("$bin" --db builtin --pose "8192,8192,$pose,0" --agl --size 720x486 --threads "$threads" --repeat 15 \
      --out "/tmp/render-ab-$n.png" 2>&1 | grep -o '[0-9.]* ms (median' | cut -d' ' -f1)
    times[n]="${times[n]:-} $ms"
    n=$((n + 1))
  done
done

median() { tr ' ' '\n' | grep . | sort -n | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
first=""
n=0
for bin in "$@"; do
  m=$(echo "${times[n]}" | median)
  [[ -n "$first" ]] || first=$m
  printf '%s  %-40s median %6.2f ms  ratio %.3f  runs:%s\n' "$view" "$bin" "$m" \
    "$(awk -v m="$m" -v f="$first" 'BEGIN {print m / f}')" "$(echo "${times[n]}" | tr ' ' '\n' | grep . | sort -n | tr '\n' ' ' | sed 's/^/ /')"
  n=$((n + 1))
done
