#!/usr/bin/env bash
# What Orca says on the web page (issue 47, docs/ACCESSIBILITY.md "Heard with Orca"): a real Orca
# (GNOME's screen reader) and a real Chromium on an X display of their own (Xvfb), an AT-SPI bus
# and a session D-Bus of their own, speech-dispatcher speaking with espeak-ng into ALSA's null
# device. `armadillo play --simulate --web 0` runs the page; keys go to Chromium as a user would
# press them (xdotool): the arrow keys read the page from its top in Orca's browse mode, then Tab
# walks every control; a panic sent as the page sends it (curl) is announced in its live region.
# Prints every line Orca spoke, from its own debug log ("SPEECH OUTPUT"), and leaves a screenshot.
# Not run by CI (it needs Orca, about 40 MB of packages); a person can run it and listen.
#
#   bash scripts/orca-listen.sh [OUTDIR]     (default: a temporary folder, said at the end)
# Needs: orca xdotool xvfb dbus speech-dispatcher-espeak-ng chromium imagemagick curl, the built CLI.
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${ARMADILLO_BIN:-$PWD/build/bin/armadillo}"
[ -x "$bin" ] || bin="$PWD/build-core/bin/armadillo"
[ -x "$bin" ] || { echo "orca-listen: build the CLI first (bash scripts/build.sh armadillo)" >&2; exit 2; }
for tool in orca xdotool xvfb-run dbus-run-session chromium import curl; do
    command -v "$tool" > /dev/null || { echo "orca-listen: $tool is missing (apt-get install orca xdotool xvfb dbus chromium imagemagick curl speech-dispatcher-espeak-ng)" >&2; exit 2; }
done
out="$(realpath -m "${1:-$(mktemp -d "${TMPDIR:-/tmp}/armadillo-orca.XXXXXX")}")"
mkdir -p "$out"

if [ -z "${ARMADILLO_ORCA_INNER:-}" ]; then
    export ARMADILLO_ORCA_INNER=1
    # A home of its own: Orca's and speech-dispatcher's settings, nothing of the user's touched.
    export HOME="$out/home" XDG_CONFIG_HOME="$out/home/.config" XDG_RUNTIME_DIR="$out/run"
    mkdir -p "$XDG_CONFIG_HOME/speech-dispatcher" "$XDG_RUNTIME_DIR"
    chmod 700 "$XDG_RUNTIME_DIR"
    cp -r /etc/speech-dispatcher/. "$XDG_CONFIG_HOME/speech-dispatcher/"
    # No sound card here: espeak-ng speaks into ALSA's null device (else speech-dispatcher never
    # answers and Orca waits on it).
    printf '%s\n' 'AudioOutputMethod "alsa"' 'AudioALSADevice "null"' 'AddModule "espeak-ng" "sd_espeak-ng" "espeak-ng.conf"' \
        'DefaultModule espeak-ng' >> "$XDG_CONFIG_HOME/speech-dispatcher/speechd.conf"
    exec xvfb-run -a -s '-screen 0 1280x1000x24' dbus-run-session -- bash "$0" "$out"
fi

pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done; }
trap cleanup EXIT
export GTK_MODULES=gail:atk-bridge ACCESSIBILITY_ENABLED=1
/usr/libexec/at-spi-bus-launcher --launch-immediately & pids+=($!)
sleep 2
orca --replace --debug-file="$out/orca.debug" > "$out/orca.out" 2>&1 & pids+=($!)
sleep 6
"$bin" play --simulate --scene theremin --seconds 120 --no-audio --web 0 2> "$out/play.err" > "$out/play.out" & pids+=($!)
for _ in $(seq 50); do grep -q 'http://127.0.0.1:[0-9]*/' "$out/play.err" 2> /dev/null && break; sleep 0.1; done
url=$(grep -o 'http://127.0.0.1:[0-9]*/' "$out/play.err" | head -1)
[ -n "$url" ] || { echo "orca-listen: play printed no address" >&2; cat "$out/play.err" >&2; exit 4; }
chromium --no-sandbox --force-renderer-accessibility --no-first-run --user-data-dir="$out/chromium" --window-size=1200,900 "$url" \
    > "$out/chromium.out" 2>&1 & pids+=($!)
sleep 12
win=$(xdotool search --onlyvisible --class chromium | head -1)
xdotool windowactivate "$win" 2> /dev/null || true
xdotool windowfocus "$win"
sleep 2
key() { xdotool key "$1"; sleep "${2:-1.2}"; }
xdotool key ctrl+Home; sleep 1
for _ in $(seq 30); do key Down; done          # browse mode: the page read line by line from the top
xdotool key ctrl+Home; sleep 1
for _ in $(seq 34); do key Tab; done           # every control, in order
# A panic from elsewhere (the stage's tablet, say), as the page itself sends it: what Orca says
# of it comes from the page's live region.
token=$(curl -s "$url" | grep -o 'armadillo-token" content="[0-9a-f]*' | grep -o '[0-9a-f]*$')
curl -s -o /dev/null -X POST -H "Origin: ${url%/}" -H "X-Armadillo-Token: $token" --data panic "${url}api/stage"
sleep 4
import -window root "$out/screen.png" 2> /dev/null || true
timeout 10 orca --quit > /dev/null 2>&1 || true   # a clean quit writes the rest of its debug log
sleep 2
grep -a 'SPEECH OUTPUT' "$out/orca.debug" | sed -E "s/^[0-9:.]+ - SPEECH OUTPUT: '(.*)' ?\{.*$/\1/" > "$out/heard.txt" || true
cat "$out/heard.txt"
echo "orca-listen: $(wc -l < "$out/heard.txt") lines heard; files in $out" >&2
