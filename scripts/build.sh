#!/usr/bin/env bash
# Configures and builds into ./build: everything (core, CLI, plugin, tests, benchmarks), or only the
# targets named (`bash scripts/build.sh armadillo` builds the command line program alone).
# ARMADILLO_NO_PLUGIN=1 skips the JUCE plugin (the core and CLI then build in about a minute).
set -euo pipefail
cd "$(dirname "$0")/.."
plugin=ON
if [ "${ARMADILLO_NO_PLUGIN:-0}" = "1" ]; then plugin=OFF; fi
# ccache, when installed, keeps rebuilds (and builds of other checkouts of this tree) short;
# CCACHE_BASEDIR makes its keys independent of where the checkout lives.
launcher=()
if command -v ccache > /dev/null; then
    export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"
    launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build -G Ninja "${launcher[@]}" -DCMAKE_BUILD_TYPE=Release -DARMADILLO_BUILD_PLUGIN=$plugin
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build -j "$(nproc)" "${targets[@]}"
