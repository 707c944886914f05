#!/bin/sh
# fieldcast-render run for real (issue 23): non-finite or out-of-range numbers are refused with a
# message naming the option and the range; the frame and its range image are written all or
# nothing (a range image that cannot be written leaves no PNG, and no temporary, behind).
set -eu
tool=$1
work=$2
rm -rf "$work"
mkdir -p "$work"

failures=0
fail() {
  echo "FAIL: $*"
  [ -f "$work/out.txt" ] && sed 's/^/    /' "$work/out.txt"
  failures=$((failures + 1))
}
render() {  # a small frame of the synthetic hills, then any extra arguments
  "$tool" --db synthetic --terrain-size 256 --agl --fov 60 --threads 1 "$@" > "$work/out.txt" 2>&1
}
good_pose=200,200,150,30,-30,0
size=48x32

# Options: every bad number is refused, naming the option and what was expected.
expect_refused() {
  pattern=$1
  shift
  if render "$@"; then
    fail "accepted: $*"
  elif ! grep -q -- "$pattern" "$work/out.txt"; then
    fail "'$*' did not say '$pattern'"
  fi
  [ ! -e "$work/bad.png" ] || fail "'$*' wrote an image"
  rm -f "$work/bad.png"
}
expect_refused "--pose: x must be a finite number from -1e+07 to 1e+07 m, got 'nan'" \
  --pose nan,200,150,30,-30,0 --out "$work/bad.png"
expect_refused "--pose: z must be a finite number from -10000 to 1e+06 m, got 'inf'" \
  --pose 200,200,inf,30,-30,0 --out "$work/bad.png"
expect_refused "--pose: heading must be a finite number from -360 to 360 degrees, got '-inf'" \
  --pose 200,200,150,-infinity,-30,0 --out "$work/bad.png"
expect_refused "--pose: pitch must be a finite number from -90 to 90 degrees, got 'nan'" \
  --pose 200,200,150,30,NAN,0 --out "$work/bad.png"
expect_refused "--pose: roll must be a finite number from -180 to 180 degrees, got '720'" \
  --pose 200,200,150,30,-30,720 --out "$work/bad.png"
expect_refused "--pose: 'abc' is not a number" --pose abc,200,150,30,-30,0 --out "$work/bad.png"
expect_refused "--fov: expected a finite number from 1 to 170 degrees, got 'nan'" \
  --pose $good_pose --fov nan --out "$work/bad.png"
expect_refused "--margin: expected a finite number from 0 to 1 of each dimension, got 'nan'" \
  --pose $good_pose --margin nan --out "$work/bad.png"
expect_refused "--quality: expected a finite number from 0.05 to 64, got 'nan'" \
  --pose $good_pose --quality nan --out "$work/bad.png"
expect_refused "--anisotropy: expected a finite number from 0 to 1000, got 'inf'" \
  --pose $good_pose --anisotropy inf --out "$work/bad.png"
expect_refused "--haze: expected a finite number from 0 to 1e+07 m, got 'nan'" \
  --pose $good_pose --haze nan --out "$work/bad.png"
expect_refused "--threads: expected an integer from 0 to 1024 threads, got '-1'" \
  --pose $good_pose --threads -1 --out "$work/bad.png"
expect_refused "--seed: expected an integer from 0 to 4294967295, got '-1'" \
  --pose $good_pose --seed -1 --out "$work/bad.png"
expect_refused "--size: expected WxH such as 720x486, W and H from 2 to 16384 pixels, got '48x32x'" \
  --pose $good_pose --size 48x32x --out "$work/bad.png"
expect_refused "--size: expected WxH such as 720x486, W and H from 2 to 16384 pixels, got '1x32'" \
  --pose $good_pose --size 1x32 --out "$work/bad.png"
expect_refused "--out $work/missing/f.png: folder $work/missing does not exist" \
  --pose $good_pose --size $size --out "$work/missing/f.png"

# All or nothing. A range image in a format nothing writes fails after the frame was rendered:
# no PNG may be left behind, an older PNG of that name stays as it was, and no temporary remains.
printf 'older' > "$work/kept.png"
if render --pose $good_pose --size $size --out "$work/kept.png" --range-out "$work/range.xyz"; then
  fail "a range image in an unknown format was accepted"
else
  grep -q "range.xyz: cannot write this format" "$work/out.txt" || fail "the range image's failure was not named"
fi
[ "$(cat "$work/kept.png")" = "older" ] || fail "the PNG was written although the range image failed"
if render --pose $good_pose --size $size --out "$work/new.png" --range-out "$work/range.xyz"; then fail "accepted range.xyz"; fi
[ ! -e "$work/new.png" ] || fail "the PNG was left behind although the range image failed"
# The other way round: the frame cannot be written, so no range image either.
if render --pose $good_pose --size $size --out "$work/frame.xyz" --range-out "$work/range.tif"; then fail "accepted frame.xyz"; fi
[ ! -e "$work/range.tif" ] || fail "the range image was left behind although the frame failed"
leftovers=$(find "$work" -name '.*tmp-*')
[ -z "$leftovers" ] || fail "temporaries left behind: $leftovers"

# And both land when both can be written.
render --pose $good_pose --size $size --out "$work/both.png" --range-out "$work/both.tif" || fail "a good render failed"
grep -q "wrote $work/both.png: 58x40" "$work/out.txt" || fail "frame not reported"
grep -q "wrote $work/both.tif: range in metres" "$work/out.txt" || fail "range image not reported"
[ -s "$work/both.png" ] && [ -s "$work/both.tif" ] || fail "frame or range image missing"
leftovers=$(find "$work" -name '.*tmp-*')
[ -z "$leftovers" ] || fail "temporaries left behind: $leftovers"

[ "$failures" -eq 0 ] || { echo "$failures checks failed"; exit 1; }
echo "fieldcast-render: option checks and all-or-nothing output OK"
