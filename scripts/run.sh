#!/usr/bin/env bash
# The README's run command: installs dependencies, builds, and starts ARMadillo.
#   with a display:      the standalone app (simulated forearm unless a device is chosen)
#   without a display,   or with --headless: `armadillo play --simulate` for 20 s with the
#   theremin, writing armadillo-session.wav, armadillo-tactile.csv and armadillo-session.csv
set -euo pipefail
cd "$(dirname "$0")/.."
headless=0
if [ "${1:-}" = "--headless" ] || [ -z "${DISPLAY:-}" ]; then headless=1; fi
bash scripts/install-deps.sh
if [ $headless = 1 ]; then
    bash scripts/build.sh armadillo   # only the command line program: no plugin, tests or benchmarks
    exec build/bin/armadillo play --scene theremin --simulate --seconds 20 \
        --out armadillo-session.wav --tactile armadillo-tactile.csv --log armadillo-session.csv
fi
bash scripts/build.sh ARMadillo_Standalone   # only the app
exec build/Source/Plugin/ARMadillo_artefacts/Release/Standalone/ARMadillo
