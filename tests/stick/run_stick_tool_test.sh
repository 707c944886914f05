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
# The same descriptor in every form a user has at hand lists the same fields: binary (as sysfs
# gives it), commented hex (hid-decode, kernel sources: 0x prefixes, commas, # and // comments),
# a hid-recorder recording (R: line) and a usbhid-dump capture.
for b in $(cat "$data/tca_yoke_boeing.hex"); do printf "\\$(printf '%03o' "0x$b")"; done > "$work/yoke.bin"
[ "$(wc -c < "$work/yoke.bin")" -eq 149 ] || { echo "could not write the binary descriptor"; exit 1; }
{
  echo "001:004:000:DESCRIPTOR         1712345678.123456"
  sed 's/^/ /' "$data/tca_yoke_boeing.hex" | tr 'a-f' 'A-F'
} > "$work/yoke.usbhid-dump"
for form in "$work/yoke.bin" "$data/tca_yoke_boeing_commented.txt" "$data/tca_yoke_boeing.hidrec" \
  "$work/yoke.usbhid-dump"; do
  "$tool" descriptor "$form" > "$work/form.txt" 2> "$work/err.txt" || { echo "$form: refused"; cat "$work/err.txt"; exit 1; }
  cmp -s "$work/desc.txt" "$work/form.txt" || { echo "$form: lists other fields"; diff "$work/desc.txt" "$work/form.txt" | head; exit 1; }
done
# Errors name the file and, in text, the line.
expect_error() {  # expect_error FILE MESSAGE
  if "$tool" descriptor "$1" > /dev/null 2> "$work/err.txt"; then echo "$1: accepted"; exit 1; fi
  grep -qF -- "$2" "$work/err.txt" || { echo "$1: expected \"$2\", got:"; cat "$work/err.txt"; exit 1; }
}
mkdir -p "$work/a_folder"
expect_error "$work/a_folder" "$work/a_folder: is a directory"
printf '\000' > "$work/zero.bin"
expect_error "$work/zero.bin" "$work/zero.bin: the descriptor declares no input field"
printf '00\n' > "$work/zero.hex"
expect_error "$work/zero.hex" "$work/zero.hex: the descriptor declares no input field"
# An output-only device (one LED report) is a valid descriptor, but not a stick.
printf '05 08 09 01 a1 01 09 4b 15 00 25 01 75 01 95 01 91 02 95 07 91 03 c0\n' > "$work/leds.hex"
expect_error "$work/leds.hex" "$work/leds.hex: the descriptor declares no input field (23 bytes, 1 output or feature fields)"
printf '# a comment\n05 01 09 04\n0x05, 0x01, zz // junk\n' > "$work/junk.hex"
expect_error "$work/junk.hex" "$work/junk.hex:3: \"zz\" is not a hex byte"
printf 'R: 5 05 01 09\n' > "$work/short.hidrec"
expect_error "$work/short.hidrec" "$work/short.hidrec:1: R: says 5 bytes, the line holds 3"
printf '05 01 09 04 a1 01\n' > "$work/cut.hex"
expect_error "$work/cut.hex" "$work/cut.hex: HID report descriptor, byte 6: 1 collection(s) not closed"
if "$tool" replay "$data/tca_yoke_boeing.hex" 2> "$work/err.txt"; then echo "a non-recording was accepted"; exit 1; fi
grep -q "tca_yoke_boeing.hex:1: expected \"fieldcast-input 1\"" "$work/err.txt" || { cat "$work/err.txt"; exit 1; }
echo "fieldcast-stick: replay, record, re-replay (identical) and descriptor (binary, commented hex, R: line, errors) OK"
