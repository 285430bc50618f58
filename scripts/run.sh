#!/usr/bin/env bash
# The README's run command: installs dependencies, builds, and starts ARMadillo.
#   with a display:      the standalone app (simulated forearm unless a device is chosen)
#   without a display,   or with --headless: `armadillo play --simulate` for 20 s with the
#   theremin, writing armadillo-session.wav, armadillo-tactile.csv and armadillo-session.csv
#   --package            builds the Debian package (scripts/package.sh) unless build/ has one,
#                        installs it with apt-get (which fetches its Depends), and starts the
#                        installed program the same way (combine with --headless)
set -euo pipefail
cd "$(dirname "$0")/.."
headless=0
package=0
for arg in "$@"; do
    case "$arg" in
        --headless) headless=1 ;;
        --package) package=1 ;;
        *) echo "usage: $0 [--headless] [--package]" >&2; exit 2 ;;
    esac
done
if [ -z "${DISPLAY:-}" ]; then headless=1; fi
run_as_root=()
if [ "$(id -u)" -ne 0 ]; then run_as_root=(sudo); fi

if [ $package = 1 ]; then
    deb=$(ls -t build/armadillo_*_amd64.deb 2>/dev/null | head -1 || true)
    if [ -z "$deb" ]; then
        bash scripts/package.sh
        deb=$(ls -t build/armadillo_*_amd64.deb | head -1)
    fi
    "${run_as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "./$deb"
    if [ $headless = 1 ]; then
        exec armadillo play --scene theremin --simulate --seconds 20 \
            --out armadillo-session.wav --tactile armadillo-tactile.csv --log armadillo-session.csv
    fi
    exec armadillo-app
fi

bash scripts/install-deps.sh
if [ $headless = 1 ]; then
    bash scripts/build.sh armadillo   # only the command line program: no plugin, tests or benchmarks
    exec build/bin/armadillo play --scene theremin --simulate --seconds 20 \
        --out armadillo-session.wav --tactile armadillo-tactile.csv --log armadillo-session.csv
fi
bash scripts/build.sh ARMadillo_Standalone   # only the app
exec build/Source/Plugin/ARMadillo_artefacts/Release/Standalone/ARMadillo
