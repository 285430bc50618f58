#!/usr/bin/env bash
# Configures and builds into ./build: everything (core, CLI, plugin, tests, benchmarks), or only the
# targets named (`bash scripts/build.sh armadillo` builds the command line program alone).
# ARMADILLO_NO_PLUGIN=1 skips the JUCE plugin (the core and CLI then build in about a minute).
set -euo pipefail
cd "$(dirname "$0")/.."
plugin=ON
if [ "${ARMADILLO_NO_PLUGIN:-0}" = "1" ]; then plugin=OFF; fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DARMADILLO_BUILD_PLUGIN=$plugin
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build -j "$(nproc)" "${targets[@]}"
