#!/usr/bin/env bash
# The install tree works on its own: `cmake --install` of ./build into a temporary prefix, then the
# installed binaries run from there, from another folder, with an empty home and no
# ARMADILLO_RESOURCES (so only what was installed can serve them). Called by check-artefacts.sh.
#   ARMADILLO_NO_PLUGIN=1  the build has no plugin: skip its files
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
prefix=$(mktemp -d /tmp/armadillo-install.XXXXXX)
work=$(mktemp -d /tmp/armadillo-user.XXXXXX)
trap 'rm -rf "$prefix" "$work"' EXIT
cmake --install "$build" --prefix "$prefix" > "$work/install.log"
fail=0
need() { if [ -e "$prefix/$1" ]; then echo "installed: $1"; else echo "NOT INSTALLED: $1"; fail=1; fi; }
need bin/armadillo
need share/man/man1/armadillo.1.gz
need share/doc/armadillo/README.md
need share/doc/armadillo/CHANGELOG.md
need share/doc/armadillo/copyright
need share/doc/armadillo/docs/INTERFACES.md
need share/doc/armadillo/examples/imu.csv
need share/doc/armadillo/examples/poses.csv
need share/doc/armadillo/examples/calibration.json
if [ "${ARMADILLO_NO_PLUGIN:-0}" != "1" ]; then
    need lib/vst3/ARMadillo.vst3/Contents/x86_64-linux/ARMadillo.so
    need lib/lv2/ARMadillo.lv2/manifest.ttl
    need bin/armadillo-app
    need share/applications/armadillo-app.desktop
    need share/icons/hicolor/scalable/apps/armadillo.svg
    need share/man/man1/armadillo-app.1.gz
    if command -v desktop-file-validate > /dev/null; then
        desktop-file-validate "$prefix/share/applications/armadillo-app.desktop" || fail=1
    fi
fi

# The installed CLI, elsewhere, as a new user: version, man page, both shipped scores, examples.
mkdir -p "$work/home"
run() { (cd "$work" && env -u ARMADILLO_RESOURCES -u XDG_DATA_HOME HOME="$work/home" "$prefix/bin/armadillo" "$@"); }
expected=$(sed -n 's/^project(ARMadillo VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
[ "$(run --version)" = "armadillo $expected" ] || { echo "installed armadillo --version is not $expected"; fail=1; }
# Read whole before grep: with pipefail, `zcat | grep -q` fails when grep stops at its first
# match and zcat is still writing (SIGPIPE), a race that a longer man page loses.
man=$(zcat "$prefix/share/man/man1/armadillo.1.gz")
grep -q "^\.SS render" <<< "$man" || { echo "man page lacks the render section"; fail=1; }
examples="$prefix/share/doc/armadillo/examples"
for score in rite-of-spring polytope; do
    run render --scene score --score "$score" --motion "$examples/poses.csv" --out "$work/$score.wav" \
        --tactile "$work/$score.csv" > /dev/null
    # 1201 motion rows → 1201 tactile rows, the closing all-off row and the header, and some motor moved.
    rows=$(wc -l < "$work/$score.csv")
    moved=$(tail -n +2 "$work/$score.csv" | cut -d, -f2- | tr ',' '\n' | grep -vc '^0$' || true)
    if [ "$rows" -eq 1203 ] && [ "$moved" -gt 0 ]; then
        echo "installed armadillo renders score $score ($moved nonzero motor levels)"
    else
        echo "installed armadillo: score $score rendered $rows rows, $moved nonzero levels"; fail=1
    fi
done
run fuse --in "$examples/imu.csv" --out "$work/q.csv" --features 2> /dev/null
run play --scene monitor --simulate --seconds 1 --no-audio --calibration "$examples/calibration.json" > "$work/play.txt"
grep -q '"packets":' "$work/play.txt" || { echo "installed armadillo play printed no summary"; fail=1; }
[ $fail = 0 ] && echo "install tree ok ($prefix)"
exit $fail
