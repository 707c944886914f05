#!/usr/bin/env bash
# Interop test of the CIGI codec against Wireshark's CIGI dissector (label interop).
# Usage: cigi_tshark_check.sh <fieldcast_cigi_capture binary> <work directory>
#
# 1. The capture writer encodes host→IG and IG→host datagrams of every packet type, in both
#    byte orders, into <dir>/cigi.pcap, and the values it sent into <dir>/expected.tsv.
# 2. `tshark -V` must dissect every frame as CIGI 3 with no malformed, unknown or expert-flagged
#    packet. The dissector is forced onto the IG port; version and byte order are left to the
#    dissector ("From Packet"), so it must recognise CIGI 3.3 and each datagram's byte order itself.
# 3. `tshark -T fields` must print, for every expected (frame, field), exactly one value equal
#    to the one sent.
# Exits 77 (skipped) when tshark is not installed.
set -euo pipefail
capture=$1 dir=$2

if ! command -v tshark >/dev/null 2>&1; then
  echo "[  SKIPPED ] tshark not installed (scripts/install-deps.sh --interop installs it)"
  exit 77
fi

rm -rf "$dir"
"$capture" "$dir"
pcap=$dir/cigi.pcap expected=$dir/expected.tsv
tshark_args=(-n -r "$pcap" -d udp.port==8004,cigi)
echo "tshark $(tshark --version | head -1 | cut -d' ' -f3): tshark ${tshark_args[*]} -V"

tshark "${tshark_args[@]}" -V >"$dir/dissection.txt" 2>"$dir/tshark.err" || {
  echo "FAIL: tshark -V exited with an error:"; cat "$dir/tshark.err"; exit 1; }
frames=$(grep -c '^Frame [0-9]*:' "$dir/dissection.txt" || true)
cigi3=$(grep -c '^Common Image Generator Interface (3)' "$dir/dissection.txt" || true)
if [[ $frames -ne 4 || $cigi3 -ne 4 ]]; then
  echo "FAIL: $frames frames, $cigi3 dissected as CIGI 3 (expected 4 and 4)"; exit 1
fi
if grep -n -i -E 'malformed|unknown|expert info|exception' "$dir/dissection.txt"; then
  echo "FAIL: tshark reports the lines above (full dissection: $dir/dissection.txt)"; exit 1
fi
for order in 'Big-Endian (0x8000)' 'Little-Endian (0x0080)'; do
  count=$(grep -c "Byte Swap: $order" "$dir/dissection.txt" || true)
  if [[ $count -ne 2 ]]; then echo "FAIL: $count datagrams read as $order, expected 2"; exit 1; fi
done

mapfile -t fields < <(cut -f2 "$expected" | awk '!seen[$0]++')
field_args=()
for f in "${fields[@]}"; do field_args+=(-e "$f"); done
tshark "${tshark_args[@]}" -T fields -E header=y -E separator=/t -E occurrence=a -e frame.number \
  "${field_args[@]}" >"$dir/fields.tsv" 2>>"$dir/tshark.err"

# Compare: numbers numerically (they are exact binary fractions, so equal), the rest as text.
awk -F'\t' '
  NR == FNR { want[$1, $2] = $3; order[++n] = $1 SUBSEP $2; next }
  FNR == 1 { for (i = 2; i <= NF; ++i) column[$i] = i; next }
  { for (name in column) got[$1, name] = $(column[name]); frames[$1] = 1 }
  END {
    bad = 0
    for (k = 1; k <= n; ++k) {
      split(order[k], key, SUBSEP)
      frame = key[1]; name = key[2]; value = got[frame, name]
      if (!(name in column)) { printf "FAIL: tshark knows no field %s\n", name; ++bad; continue }
      if (value == "" || index(value, ",") > 0) {
        printf "FAIL: frame %s %s: tshark printed \"%s\", expected one value %s\n", frame, name, value, want[frame, name]
        ++bad; continue
      }
      expect = want[frame, name]
      numeric = (value ~ /^-?[0-9.]+([eE][-+]?[0-9]+)?$/ && expect ~ /^-?[0-9.]+([eE][-+]?[0-9]+)?$/)
      if ((numeric && value + 0 != expect + 0) || (!numeric && value != expect)) {
        printf "FAIL: frame %s %s: tshark %s, sent %s\n", frame, name, value, expect; ++bad
      }
    }
    printf "%d field values compared, %d differ\n", n, bad
    exit bad > 0
  }' "$expected" "$dir/fields.tsv"
echo "PASS: 4 CIGI 3.3 datagrams (host→IG and IG→host, big- and little-endian), nothing malformed or unknown"
