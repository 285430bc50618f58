#!/usr/bin/env bash
# The package on its own, as a user gets it: a clean Debian root (debootstrap, once; then a fresh
# copy for every run) gets only the .deb, installed with `apt-get install ./armadillo_*.deb`
# (apt fetches the Depends), while the build tree is moved out of reach. Inside the root:
#   - JUCE's VST3 host (Tests/Plugin/HostScenes.cpp, copied in as a program of its own) loads
#     /usr/lib/vst3/ARMadillo.vst3 and plays every scene, the score scene with both shipped scores;
#   - pedalboard (PyPI; a third-party host) loads the same VST3 and plays every scene
#     (scripts/play_scenes.py; skipped with a message when PyPI is out of reach);
#   - the installed `armadillo` renders both scores from / and from /tmp with an empty HOME;
#   - Debian's Pd opens the Pd objects' help patches from /usr/lib/pd/extra/armadillo.
# Usage: bash scripts/check-package.sh [PACKAGE.deb]   (default: the newest build/armadillo_*.deb)
# Needs root (chroot, mount) and debootstrap (install-deps.sh --packaging).
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
deb=$(readlink -f "${1:-$(ls -t build/armadillo_*_amd64.deb | head -1)}")
host=$(readlink -f build/Tests/Plugin/armadillo_host_scenes)
[ -f "$deb" ] || { echo "no package: run scripts/package.sh first"; exit 1; }
[ -x "$host" ] || { echo "no build/Tests/Plugin/armadillo_host_scenes: build with the plugin and tests"; exit 1; }
[ "$(id -u)" -eq 0 ] || { echo "check-package: needs root (chroot)"; exit 1; }
version=$(dpkg-deb -f "$deb" Version)
base=${ARMADILLO_CLEAN_ROOT:-/var/tmp/armadillo-clean-root}
root=$(mktemp -d /var/tmp/armadillo-check-root.XXXXXX)
away="$repo.build-away.$$"

cleanup() {
    for m in dev/pts dev proc sys; do umount "$root/$m" 2> /dev/null || true; done
    rm -rf --one-file-system "$root"
    [ -d "$away" ] && mv "$away" "$repo/build"
    true
}
trap cleanup EXIT

if [ ! -x "$base/usr/bin/python3" ]; then
    echo "check-package: making a clean Debian root in $base (debootstrap, once)"
    debootstrap --variant=minbase --include=python3,python3-venv,ca-certificates bookworm "$base" http://deb.debian.org/debian > /dev/null
fi
cp -a "$base/." "$root/"
cp /etc/resolv.conf "$root/etc/resolv.conf"
mkdir -p "$root/opt/check"
cp "$deb" "$root/opt/check/"
cp "$host" "$repo/scripts/play_scenes.py" "$root/opt/check/"
[ -d "${ARMADILLO_WHEELS:-/nonexistent}" ] && cp -r "$ARMADILLO_WHEELS" "$root/opt/check/wheels"
mount -t proc proc "$root/proc"
mount --bind /dev "$root/dev"
mount --bind /dev/pts "$root/dev/pts"
mount -t sysfs sysfs "$root/sys"

# From here on the build tree is gone: nothing can come from it.
mv "$repo/build" "$away"
echo "check-package: build tree moved away; $(basename "$deb") into a clean bookworm root"
in_root() { chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 "$@"; }
in_root sh -c 'apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends ./opt/check/'"$(basename "$deb")"' > /opt/check/apt.log 2>&1 && cd /opt/check' \
    || { tail -20 "$root/opt/check/apt.log"; exit 1; }
in_root dpkg -s armadillo | sed -n 's/^\(Version\|Depends\):/  installed \1:/p'
fail=0

echo "== JUCE's VST3 host on /usr/lib/vst3/ARMadillo.vst3"
in_root sh -c 'cd / && /opt/check/armadillo_host_scenes /usr/lib/vst3/ARMadillo.vst3 '"$version" || fail=1

echo "== pedalboard on /usr/lib/vst3/ARMadillo.vst3"
# pedalboard's own wheel needs libatomic1 (the host's dependency, not the package's).
if in_root sh -c 'DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libatomic1 > /dev/null && python3 -m venv /opt/pb && if [ -d /opt/check/wheels ]; then /opt/pb/bin/pip install -q --no-index --find-links /opt/check/wheels pedalboard; else /opt/pb/bin/pip install -q pedalboard; fi' > "$root/opt/check/pip.log" 2>&1; then
    in_root timeout 900 sh -c 'cd /tmp && /opt/pb/bin/python /opt/check/play_scenes.py /usr/lib/vst3/ARMadillo.vst3 '"$version" || fail=1
else
    echo "pedalboard could not be installed (no PyPI?): skipped"; tail -3 "$root/opt/check/pip.log"
fi

echo "== the installed armadillo, from / and from /tmp, empty HOME, no ARMADILLO_RESOURCES"
in_root sh -c 'mkdir -p /tmp/u && armadillo --version'
for dir in / /tmp; do
    for score in rite-of-spring polytope; do
        in_root sh -c "cd $dir && HOME=/tmp/u armadillo render --scene score --score $score \
            --motion /usr/share/doc/armadillo/examples/poses.csv --out /tmp/$score.wav --tactile /tmp/$score.csv > /dev/null" || fail=1
        moved=$(tail -n +2 "$root/tmp/$score.csv" | cut -d, -f2- | tr ',' '\n' | grep -vc '^0$' || true)
        rows=$(($(wc -l < "$root/tmp/$score.csv") - 1))
        echo "render --scene score --score $score from $dir: $rows tactile rows, $moved nonzero motor levels"
        [ "$moved" -gt 0 ] || fail=1
    done
done
in_root sh -c 'HOME=/tmp/u armadillo resources --scores | tr "\n" " "'; echo

echo "== Pure Data's [armadillo] and [armadillo~] from /usr/lib/pd/extra/armadillo (Debian's puredata-core)"
if in_root sh -c 'DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends puredata-core > /dev/null 2>&1'; then
    # Every help patch and the example open with no "couldn't create" and no error (docs/PUREDATA.md).
    printf '#N canvas 0 0 300 200 12;\n#X obj 10 10 loadbang;\n#X obj 10 40 delay 2000;\n#X msg 10 70 \\; pd quit;\n#X connect 0 0 1 0;\n#X connect 1 0 2 0;\n' > "$root/opt/check/quit.pd"
    for patch in "$root"/usr/lib/pd/extra/armadillo/*.pd; do
        name=$(basename "$patch")
        out=$(in_root sh -c "cd /tmp && timeout 60 pd -nogui -nosound -stderr -open /usr/lib/pd/extra/armadillo/$name -open /opt/check/quit.pd 2>&1")
        if grep -qi "couldn't create\|error" <<< "$out"; then echo "$name: FAILED"; echo "$out" | grep -i "couldn't create\|error"; fail=1; else echo "$name: opens"; fi
    done
else
    echo "puredata-core could not be installed: skipped"
fi
[ $fail = 0 ] && echo "check-package: ok" || echo "check-package: FAILED"
exit $fail
