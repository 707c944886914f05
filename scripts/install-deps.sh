#!/usr/bin/env bash
# Installs every Debian 12 package Fieldcast needs to build, test and run its demo.
# Idempotent: packages already present are skipped, so a second run costs one dpkg query.
# Usage: scripts/install-deps.sh [--interop]   (--interop adds the third-party judges:
#        ffprobe, GStreamer, tshark, clang's libFuzzer)
set -euo pipefail

build_packages=(
  build-essential cmake ninja-build pkg-config git
  libglm-dev libeigen3-dev
  libopencv-dev  # the only package that ships OpenCVConfig.cmake
  libopenimageio-dev openimageio-tools  # OIIO's CMake config names the tools' binaries
  libgpiod-dev libusb-1.0-0-dev libevdev-dev
  libtomlplusplus-dev libcli11-dev libspdlog-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libzstd-dev libxxhash-dev
  libhwy-dev  # Google Highway: SIMD kernels dispatched at run time (prp_warp)
  libembree-dev  # Embree 3: the independent renderer fieldcast_bench_table times beside the caster
  libtiff-dev  # GeoTIFF tags for terrain import (ig_core)
  libproj-dev  # PROJ: geographic DEMs reprojected at import, the database georeference (ig_core)
  libnova-dev  # the sun's position for a CIGI host's date and time of day (app)
  nlohmann-json3-dev  # the JSON run summary
  gnuplot-nox  # the plots of fieldcast-latency's report (tools/latency)
)
interop_packages=(
  ffmpeg
  gstreamer1.0-tools gstreamer1.0-plugins-base gstreamer1.0-plugins-good
  tshark
  clang-14 libclang-rt-14-dev
  gdal-bin  # GDAL-written GeoTIFFs for the terrain import interop test (ig_core)
  # io_bridge sinks: the live-window test runs against a virtual X server
  xvfb xauth
)

wanted=("${build_packages[@]}")
if [[ "${1:-}" == "--interop" ]]; then wanted+=("${interop_packages[@]}"); fi

missing=()
for pkg in "${wanted[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$pkg")
  fi
done
if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#wanted[@]} packages present"
  exit 0
fi

if [[ $(id -u) -ne 0 ]]; then SUDO=sudo; else SUDO=; fi
echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
# tshark asks whether non-root users may capture; answer "no" without a prompt.
echo "wireshark-common wireshark-common/install-setuid boolean false" | $SUDO debconf-set-selections
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
