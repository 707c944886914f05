#!/bin/sh
# fieldcast-stick end to end: replay a recording, re-record it through the tool, replay the copy
# (must print identical ControlStates), and parse a descriptor file.
set -eu
tool=$1
data=$2
work=$3
mkdir -p "$work"
"$tool" replay "$data/saitek_roll.rec" > "$work/a.csv" 2> "$work/bindings.txt"
lines=$(wc -l < "$work/a.csv")
[ "$lines" -eq 102 ] || { echo "expected 102 lines (header, 100 frames, the loss), got $lines"; exit 1; }
[ "$(tail -n 1 "$work/a.csv")" = "# device lost" ] || { echo "the recorded loss was not replayed"; exit 1; }
grep -q "roll: X" "$work/bindings.txt" || { echo "bindings not printed"; cat "$work/bindings.txt"; exit 1; }
"$tool" record "replay:$data/saitek_roll.rec" "$work/copy.rec" --duration 20 > /dev/null
"$tool" replay "$work/copy.rec" > "$work/b.csv" 2> /dev/null
cmp "$work/a.csv" "$work/b.csv" || { echo "re-recorded replay differs"; diff "$work/a.csv" "$work/b.csv" | head; exit 1; }
"$tool" descriptor "$data/tca_yoke_boeing.hex" > "$work/desc.txt"
grep -q "report 1 Input   64 bytes" "$work/desc.txt" || { echo "descriptor summary wrong"; cat "$work/desc.txt"; exit 1; }
if "$tool" replay "$data/tca_yoke_boeing.hex" 2> "$work/err.txt"; then echo "a non-recording was accepted"; exit 1; fi
grep -q "tca_yoke_boeing.hex:1: expected \"fieldcast-input 1\"" "$work/err.txt" || { cat "$work/err.txt"; exit 1; }
echo "fieldcast-stick: replay, record, re-replay (identical) and descriptor OK"
