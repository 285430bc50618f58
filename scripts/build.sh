#!/usr/bin/env bash
# Configures and builds everything (core, CLI, plugin, tests, benchmarks) into ./build.
# ARMADILLO_NO_PLUGIN=1 skips the JUCE plugin (the core and CLI then build in about a minute).
set -euo pipefail
cd "$(dirname "$0")/.."
plugin=ON
if [ "${ARMADILLO_NO_PLUGIN:-0}" = "1" ]; then plugin=OFF; fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DARMADILLO_BUILD_PLUGIN=$plugin
cmake --build build -j "$(nproc)"
