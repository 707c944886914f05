#!/bin/sh
# fieldcast-sculpt run for real (issue 20): the shipped models (config/models) come out of their
# drawings byte for byte, and out of drawings made again; a placement list names them and
# fieldcast-db places them; bad photographs and options are refused with the reason.
set -eu
sculpt=$1
draw=$2
models=$3
db=$4
work=$5
rm -rf "$work"
mkdir -p "$work"

failures=0
fail() {
  echo "FAIL: $*"
  [ -f "$work/out.txt" ] && sed 's/^/    /' "$work/out.txt"
  failures=$((failures + 1))
}

# sculpt_model <drawings folder> <model> <height m> <output>
sculpt_model() {
  "$sculpt" --side "$1/$2/side.png" --front "$1/$2/front.png" --top "$1/$2/top.png" --height "$3" --key 00ff00 \
    -o "$4" > "$work/out.txt" 2>&1
}

# The shipped models, from the shipped drawings and from drawings made again (the heights are
# config/models/README.md's)
"$draw" "$work/drawn" > /dev/null 2>&1 || fail "fieldcast-draw-models failed"
for model in van:2.4 cottage:8 aircraft:3; do
  name=${model%%:*}
  height=${model#*:}
  sculpt_model "$models" "$name" "$height" "$work/$name.vox" || fail "sculpting the shipped $name failed"
  cmp -s "$work/$name.vox" "$models/$name.vox" || fail "the shipped $name.vox is not what its drawings sculpt to"
  sculpt_model "$work/drawn" "$name" "$height" "$work/$name-drawn.vox" || fail "sculpting the redrawn $name failed"
  cmp -s "$work/$name-drawn.vox" "$models/$name.vox" || fail "the redrawn $name does not sculpt to the shipped $name.vox"
done
sculpt_model "$models" cottage 8 "$work/c.vox"
grep -q "18 x 12 x 16 voxels of 0.50 m" "$work/out.txt" || fail "the cottage is not 18 x 12 x 16 voxels"
grep -q "coloured from the top, .* from the side, .* from the front" "$work/out.txt" || fail "no colour counts"

# A placement list names them by path, relative to the list or absolute
cp "$models/van.vox" "$work/"
cat > "$work/places.csv" <<CSV
model,x,y,heading,scale
van.vox,100,100,30,1
$models/cottage.vox,130,110,0,1
house,160,100,0,1
CSV
"$db" build --builtin --no-objects --size 128 --objects "$work/places.csv" -o "$work/placed.fctdb" > "$work/out.txt" 2>&1 ||
  fail "fieldcast-db could not place the sculpted models"
grep -q "3 objects placed (0 off the grid)" "$work/out.txt" || fail "the three objects were not all placed"
printf 'model,x,y\nlorry.vox,100,100\n' > "$work/missing.csv"
if "$db" build --builtin --no-objects --size 128 --objects "$work/missing.csv" -o "$work/m.fctdb" > "$work/out.txt" 2>&1; then
  fail "a missing .vox model was taken"
fi
grep -q "lorry.vox: cannot open the .vox file" "$work/out.txt" || fail "a missing .vox model is not named"

# Refusals: no key on RGB photographs, a bad key, a height out of range, a top view turned
if "$sculpt" --side "$models/van/side.png" --front "$models/van/front.png" --top "$models/van/top.png" --height 2.4 \
  -o "$work/x.vox" > "$work/out.txt" 2>&1; then
  fail "RGB photographs without a key were taken"
fi
grep -q "no alpha channel to separate the object; give the background's key colour" "$work/out.txt" ||
  fail "no key: the reason is not given"
if "$sculpt" --side "$models/van/side.png" --front "$models/van/front.png" --top "$models/van/top.png" --height 2.4 \
  --key green -o "$work/x.vox" > "$work/out.txt" 2>&1; then
  fail "a key of 'green' was taken"
fi
grep -q "expected a colour as rrggbb" "$work/out.txt" || fail "a bad key: the reason is not given"
if "$sculpt" --side "$models/van/side.png" --front "$models/van/front.png" --top "$models/van/top.png" --height 0 \
  --key 00ff00 -o "$work/x.vox" > "$work/out.txt" 2>&1; then
  fail "a height of 0 was taken"
fi
grep -q "expected a finite number from 0.5 to 128 m" "$work/out.txt" || fail "a height of 0: the range is not given"
if "$sculpt" --side "$models/van/side.png" --front "$models/van/front.png" --top "$models/van/side.png" --height 2.4 \
  --key 00ff00 -o "$work/x.vox" > "$work/out.txt" 2>&1; then
  fail "a side photograph as the top was taken"
fi
grep -q "the top view's object is" "$work/out.txt" || fail "a wrong top view: the reason is not given"

[ "$failures" -eq 0 ] || { echo "$failures check(s) failed"; exit 1; }
echo "sculpt tool: all checks passed"
