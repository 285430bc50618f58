#!/usr/bin/env bash
# Validates the built VST3 with Tracktion's pluginval at strictness 10, RUNS times (default 20;
# its tests use a random seed each run, and the races it finds show in a share of runs), headless
# under Xvfb. pluginval is not packaged in Debian: give a checkout of its sources
# (https://github.com/Tracktion/pluginval); it is built once into build-pluginval/ against
# Debian's JUCE (tools/pluginval/CMakeLists.txt). Not part of CI (it needs that checkout).
# Usage: bash scripts/pluginval.sh PLUGINVAL_CHECKOUT [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
src="$(realpath "${1:?give a pluginval checkout}")"
runs="${2:-20}"
vst3="$PWD/build/Source/Plugin/ARMadillo_artefacts/Release/VST3/ARMadillo.vst3"
[ -d "$vst3" ] || { echo "build the plugin first: bash scripts/build.sh ARMadillo_VST3" >&2; exit 4; }
cmake -S tools/pluginval -B build-pluginval -DPV_SRC="$src" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build-pluginval -j "$(nproc)"
exe="$(find build-pluginval -type f -name pluginval -perm -u+x | head -1)"
pass=0; fail=0
for i in $(seq "$runs"); do
    if xvfb-run -a "$exe" --strictness-level 10 --validate-in-process --skip-gui-tests --timeout-ms 600000 "$vst3" > "build-pluginval/run-$i.log" 2>&1; then
        pass=$((pass + 1))
    else
        fail=$((fail + 1)); echo "run $i failed: build-pluginval/run-$i.log" >&2; grep '!!!' "build-pluginval/run-$i.log" >&2 || true
    fi
done
echo "pluginval strictness 10: $pass of $runs runs passed"
[ "$fail" = 0 ]
