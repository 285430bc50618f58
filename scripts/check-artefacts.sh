#!/usr/bin/env bash
# The built files a user is told about in the README must exist, `armadillo --help` must list
# every subcommand of docs/INTERFACES.md, and the install tree must work on its own
# (scripts/check-install.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
fail=0
need() { if [ -e "$1" ]; then echo "artefact ok: $1"; else echo "MISSING artefact: $1"; fail=1; fi; }
need build/bin/armadillo
if command -v avr-g++ > /dev/null; then   # the reference firmware (docs/HARDWARE.md)
    need build/firmware/avr/armadillo-mega2560.hex
    need build/firmware/avr/armadillo-mega2560.elf
fi
if [ "${ARMADILLO_NO_PLUGIN:-0}" != "1" ]; then
    need "build/Source/Plugin/ARMadillo_artefacts/Release/VST3/ARMadillo.vst3"
    need "build/Source/Plugin/ARMadillo_artefacts/Release/LV2/ARMadillo.lv2"
    need "build/Source/Plugin/ARMadillo_artefacts/Release/Standalone/ARMadillo"
fi
help=$(build/bin/armadillo --help)
for c in ports fuse render play braille resources touch-profile; do
    grep -q "^  $c " <<< "$help" || { echo "armadillo --help does not list '$c'"; fail=1; }
done
bash scripts/check-install.sh build || fail=1
exit $fail
