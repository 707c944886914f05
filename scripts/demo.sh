#!/usr/bin/env bash
# The main job: installs what is missing, builds Fieldcast and runs the service.
# Safe to run any number of times.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target fieldcast

./build/app/fieldcast --version
./build/app/fieldcast --check-config --config config/fieldcast.toml
