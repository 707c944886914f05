#!/bin/sh
# fieldcast-db run for real (issue 23): `info` reports the data's own height range beside the
# quantisation's, and the georeference; every numeric option is checked with a message naming it and the range; an
# output folder that cannot be written is refused before the import.
set -eu
tool=$1
work=$2
rm -rf "$work"
mkdir -p "$work"

# Every check runs; the failures are listed and counted.
failures=0
fail() {
  echo "FAIL: $*"
  [ -f "$work/out.txt" ] && sed 's/^/    /' "$work/out.txt"
  failures=$((failures + 1))
}

# A 20 x 16 ESRI ASCII grid, heights 100 + 5 x + 2 y' (y' from the south): 100 m at the
# south-west corner, 100 + 95 + 30 = 225 m at the north-east one, so the lowest voxel is in the
# first 16 x 16 tile and the highest in the second.
asc="$work/slope.asc"
awk 'BEGIN {
  w = 20; h = 16
  printf "ncols %d\nnrows %d\nxllcorner 0\nyllcorner 0\ncellsize 10\nNODATA_value -9999\n", w, h
  for (r = 0; r < h; ++r) {            # northern row first
    y = h - 1 - r
    line = ""
    for (x = 0; x < w; ++x) line = line sprintf("%s%d", x ? " " : "", 100 + 5 * x + 2 * y)
    print line
  }
}' > "$asc"

# Item 3: info prints the data's range (from the tiles) and the quantisation's, labelled.
"$tool" build --dem "$asc" --tile-shift 4 --threads 1 -o "$work/slope.fctdb" > "$work/out.txt" 2>&1 ||
  { fail "build of a small DEM failed"; exit 1; }
"$tool" info "$work/slope.fctdb" > "$work/out.txt" 2>&1 || fail "info failed"
grep -q "heights     data 100.00 .. 225.00 m (lowest and highest voxel, from all 2 level-0 tiles)" "$work/out.txt" ||
  fail "info does not report the data's own height range 100 .. 225 m"
grep -q "quantised   z = 100.000 + 0.0100 \* q, q 0..65535: can hold 100.00 .. 755.35 m" "$work/out.txt" ||
  fail "info does not report the quantisation range, labelled as such"

# Item 4: every bad number is refused, naming the option and what was expected.
expect_refused() {
  pattern=$1
  shift
  if "$tool" "$@" > "$work/out.txt" 2>&1; then
    fail "accepted: $*"
  elif ! grep -q -- "$pattern" "$work/out.txt"; then
    fail "'$*' did not say '$pattern'"
  fi
  [ ! -e "$work/bad.fctdb" ] || fail "'$*' wrote a database"
  rm -f "$work/bad.fctdb"
}
expect_refused "--nodata: expected a finite number, got 'abc'" build --dem "$asc" --nodata abc -o "$work/bad.fctdb"
expect_refused "--nodata: expected a finite number, got 'nan'" build --dem "$asc" --nodata nan -o "$work/bad.fctdb"
expect_refused "--dem-spacing: expected a finite number from 0.01 to 100000 m, got '-1'" \
  build --dem "$asc" --dem-spacing -1 -o "$work/bad.fctdb"
expect_refused "--dem-spacing: expected a finite number from 0.01 to 100000 m, got '1e-7'" \
  build --dem "$asc" --dem-spacing 1e-7 -o "$work/bad.fctdb"
expect_refused "--vertical-scale: expected a finite number from 1e-06 to 1000 m per count, got '0'" \
  build --dem "$asc" --vertical-scale 0 -o "$work/bad.fctdb"
expect_refused "--vertical-offset: expected a finite number from -100000 to 100000 m, got 'inf'" \
  build --dem "$asc" --vertical-offset inf -o "$work/bad.fctdb"
expect_refused "--spacing: expected a finite number from 0.01 to 100000 m, got 'nan'" \
  build --builtin --size 64 --spacing nan -o "$work/bad.fctdb"
expect_refused "--size: expected an integer from 64 to 32768 voxels, got '8'" build --builtin --size 8 -o "$work/bad.fctdb"
expect_refused "--seed: expected a whole number from 0 to 18446744073709551615, got '-1'" \
  build --builtin --size 64 --seed -1 -o "$work/bad.fctdb"
expect_refused "--threads: expected an integer from 0 to 1024 threads, got '-2'" \
  build --dem "$asc" --threads -2 -o "$work/bad.fctdb"
expect_refused "--zstd-level: expected an integer from 1 to 22, got '99'" \
  build --dem "$asc" --zstd-level 99 -o "$work/bad.fctdb"
expect_refused "--sun-elevation: expected a finite number from 0 to 90 degrees, got '-inf'" \
  build --dem "$asc" --sun-elevation -inf -o "$work/bad.fctdb"
expect_refused "--sun-azimuth: expected a finite number from 0 to 360 degrees, got '400'" \
  build --dem "$asc" --sun-azimuth 400 -o "$work/bad.fctdb"
expect_refused "--tile-shift: expected an integer from 4 to 11, got '3'" \
  build --dem "$asc" --tile-shift 3 -o "$work/bad.fctdb"
expect_refused "--raw-size: expected WxH with W and H from 1 to 262144 voxels, got '-5x10'" \
  build --dem "$asc" --raw-size -5x10 -o "$work/bad.fctdb"
expect_refused "--raw-type: " build --dem "$asc" --raw-type int8 -o "$work/bad.fctdb"
expect_refused "--level: expected an integer from 0 to 31, got '-3'" \
  preview "$work/slope.fctdb" --level -3 -o "$work/bad.png"
expect_refused "--spacing: expected a finite number from 0.01 to 100000 m, got '0'" landmarks --spacing 0
# A file whose own spacing is absurd (a DEM in degrees read as metres) is refused after the import.
sed 's/^cellsize 10$/cellsize 1e-7/' "$asc" > "$work/tiny.asc"
expect_refused "tiny.asc: voxel spacing 1e-07 m (from the file): expected 0.01 to 100000 m" \
  build --dem "$work/tiny.asc" -o "$work/bad.fctdb"

# Item 5: an output folder that does not exist is refused before the DEM is read at all (the
# import line, printed after reading, must not appear).
expect_refused "-o $work/missing/x.fctdb: folder $work/missing does not exist" \
  build --dem "$asc" -o "$work/missing/x.fctdb"
if grep -q "voxels, spacing" "$work/out.txt"; then fail "the DEM was imported before the output folder was checked"; fi
expect_refused "-o $work: is a folder" build --dem "$asc" -o "$work"
: > "$work/plainfile"
expect_refused "plainfile is not a folder" build --dem "$asc" -o "$work/plainfile/x.fctdb"
[ ! -e "$work/missing" ] || fail "a folder was created"

# Item 2: info prints the georeference: none for a grid without a CRS (and how the host link
# then places latitude/longitude) ...
"$tool" info "$work/slope.fctdb" > "$work/out.txt" 2>&1 || fail "info failed"
grep -q "Fieldcast terrain database, version 3" "$work/out.txt" || fail "info does not say version 3"
grep -q "georef      none (no CRS); latitude/longitude map onto the local tangent plane at 46.000000 N, 7.000000 E" \
  "$work/out.txt" || fail "info does not say the database has no georeference and where the tangent plane is"
# ... and, from GeoTIFFs written by GDAL (when gdal-bin is installed), the CRS and where the grid
# lies: a UTM grid keeps its EPSG code; a grid in degrees becomes a local transverse Mercator; a
# striped file cut short is refused (items 1 and 2).
if command -v gdal_translate > /dev/null 2>&1; then
  gdal_translate -q -of GTiff -a_srs EPSG:32633 -a_ullr 640000 5200160 640200 5200000 -ot Float32 \
    "$asc" "$work/utm.tif"
  "$tool" build --dem "$work/utm.tif" --tile-shift 4 --threads 1 -o "$work/utm.fctdb" > /dev/null 2>&1 ||
    fail "build of a UTM GeoTIFF failed"
  "$tool" info "$work/utm.fctdb" > "$work/out.txt" 2>&1 || fail "info failed"
  grep -q "georef      WGS 84 / UTM zone 33N (EPSG:32633): world x, y are its easting and northing" "$work/out.txt" ||
    fail "info does not name the UTM CRS"
  grep -q "crs         EPSG:32633" "$work/out.txt" || fail "info does not print the CRS as stored"
  # Voxel (0, 0) centre at (640005, 5200005): 46.937... N, 16.8392... E (gdaltransform agrees).
  grep -q "corners     voxel centres: south-west 46.93" "$work/out.txt" || fail "info does not place the corners"
  gdal_translate -q -of GTiff -a_srs EPSG:4326 -a_ullr 7.0 47.0 7.01 46.99 -ot Float32 "$asc" "$work/deg.tif"
  "$tool" build --dem "$work/deg.tif" --tile-shift 4 --threads 1 -o "$work/deg.fctdb" > /dev/null 2>&1 ||
    fail "build of a GeoTIFF in degrees failed"
  "$tool" info "$work/deg.fctdb" > "$work/out.txt" 2>&1 || fail "info failed"
  grep -q 'crs         PROJCRS\["Local transverse Mercator at 46.995000, 7.005000 on WGS 84 (Fieldcast)"' \
    "$work/out.txt" || fail "info does not print the local transverse Mercator of a grid in degrees"
  grep -q "corners     voxel centres: south-west 46.990" "$work/out.txt" || fail "the degree grid is misplaced"
  gdal_translate -q -of GTiff -a_srs EPSG:32633 -ot Int16 -co COMPRESS=LZW -co BLOCKYSIZE=2 "$asc" "$work/lzw.tif"
  head -c 700 "$work/lzw.tif" > "$work/cut.tif"
  expect_refused "cut.tif: cut short: strips" build --dem "$work/cut.tif" -o "$work/bad.fctdb"
else
  echo "SKIP: GeoTIFF georeference checks (gdal_translate not found; scripts/install-deps.sh --interop)"
fi

# Objects: the sculpted van placed on flat ground at its own 0.5 m voxels; its body over the gap
# between its wheels stands as complex sticks, which info counts and verify reads back.
models=$(cd "$(dirname "$0")/../../../config/models" && pwd)
awk 'BEGIN {
  printf "ncols 40\nnrows 40\nxllcorner 0\nyllcorner 0\ncellsize 0.5\nNODATA_value -9999\n"
  for (r = 0; r < 40; ++r) { line = ""; for (x = 0; x < 40; ++x) line = line (x ? " " : "") "100"; print line }
}' > "$work/flat.asc"
printf 'model,x,y,heading,scale\n%s/van.vox,10,10,0,1\n' "$models" > "$work/van.csv"
"$tool" build --dem "$work/flat.asc" --objects "$work/van.csv" --tile-shift 4 --threads 1 -o "$work/van.fctdb" \
  > "$work/out.txt" 2>&1 || fail "build with the van placed failed"
"$tool" info "$work/van.fctdb" > "$work/out.txt" 2>&1 || fail "info of the van's database failed"
grep -Eq "sticks      40 level-0 voxels carry one; table of [0-9]+ entries \([0-9]+ uniform, [0-9]+ textured, [1-9][0-9]* complex\)" \
  "$work/out.txt" || fail "info does not count the van's 40 columns and its complex sticks"
"$tool" verify "$work/van.fctdb" > "$work/out.txt" 2>&1 || fail "verify of the van's database failed"

[ "$failures" -eq 0 ] || { echo "$failures checks failed"; exit 1; }
echo "fieldcast-db: data height range, georeference, option checks and output folder check OK"
