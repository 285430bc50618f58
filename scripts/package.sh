#!/usr/bin/env bash
# Builds the Debian package build/armadillo_<version>_amd64.deb (plugin included) with CPack and
# runs lintian on it: errors fail the script, warnings are printed.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --packaging
[ -x build/bin/armadillo ] && [ -d build/Source/Plugin ] || ARMADILLO_NO_PLUGIN=0 bash scripts/build.sh
cmake --build build -j "$(nproc)"
(cd build && cpack -G DEB)
deb=$(ls -t build/armadillo_*_amd64.deb | head -1)
echo "package: $deb"
dpkg-deb --info "$deb" | sed -n 's/^ \(Package\|Version\|Section\|Depends\|Maintainer\):/  \1:/p'
if command -v lintian > /dev/null; then
    lintian --info "$deb" | tee build/lintian.txt || true
    if grep -q '^E:' build/lintian.txt; then echo "lintian reports errors"; exit 1; fi
    echo "lintian: no errors ($(grep -c '^W:' build/lintian.txt || true) warnings)"
else
    echo "lintian is not installed: skipped (apt-get install lintian)"
fi
