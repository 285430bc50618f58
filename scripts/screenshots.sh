#!/usr/bin/env bash
# Screenshots of the standalone app for docs/images (issue 24), taken under Xvfb with a fresh
# home folder (so the app starts as on a first run: the welcome shows, no device, and in a
# container no sound card). Needs: xvfb imagemagick xdotool (apt-get install -y xvfb imagemagick
# xdotool) and the built app (bash scripts/build.sh ARMadillo_Standalone).
# Usage: bash scripts/screenshots.sh [OUTDIR]   (default docs/images)
#        ARMADILLO_SHOTS=performance bash scripts/screenshots.sh   (only the performance view)
set -euo pipefail
cd "$(dirname "$0")/.."
app="$PWD/build/Source/Plugin/ARMadillo_artefacts/Release/Standalone/ARMadillo"
out="$(realpath -m "${1:-docs/images}")"
mkdir -p "$out"
[ -x "$app" ] || { echo "build the app first: bash scripts/build.sh ARMadillo_Standalone" >&2; exit 4; }
if [ -z "${ARMADILLO_SHOTS_INNER:-}" ]; then
    export ARMADILLO_SHOTS_INNER=1
    exec xvfb-run -a -s '-screen 0 3000x2100x24' bash "$0" "$out"
fi

home="$(mktemp -d)"
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$home"' EXIT
export HOME="$home" XDG_CONFIG_HOME="$home/.config" XDG_RUNTIME_DIR="$home"

start_app() {   # $1 = scale (1 or 2)
    ARMADILLO_UI_SCALE="$1" "$app" 2> "$home/app.log" &
    pid=$!
    for _ in $(seq 100); do
        win=$(xdotool search --onlyvisible --name '^ARMadillo$' 2>/dev/null | head -1 || true)
        [ -n "$win" ] && break
        sleep 0.2
    done
    [ -n "$win" ] || { echo "the app's window did not appear" >&2; cat "$home/app.log" >&2; exit 4; }
    xdotool windowmove "$win" 0 0
    xdotool windowfocus "$win"   # no window manager under Xvfb: give the app the keyboard
    sleep 2
}
stop_app() { kill "$pid"; wait "$pid" 2>/dev/null || true; }
size() { xdotool windowsize "$win" "$1" "$2"; sleep 1.5; }
shot() {   # $1 = name; crops to the window, keeps the PNG small (8-bit palette)
    sleep 0.8
    eval "$(xdotool getwindowgeometry --shell "$win")"
    import -window root -crop "${WIDTH}x${HEIGHT}+${X}+${Y}" +repage -depth 8 -colors 256 -define png:compression-level=9 "PNG8:$out/$1.png"
    echo "$out/$1.png"
}
key() { xdotool key --delay 150 "$@"; sleep 0.4; }
type_text() { xdotool type --delay 80 "$1"; sleep 0.3; }
# The device panel with the guided calibration, keyboard only: F1, Shift+Tab x6 from Close to
# "Device panel" (focus lands on the port list), pick the simulated forearm, Tab to Connect,
# then Tab x3 to Calibrate...
calibration_shot() {   # $1 = name
    key F1
    key shift+Tab shift+Tab shift+Tab shift+Tab shift+Tab shift+Tab Return
    key Return Down Return
    key Tab Return
    sleep 2
    key Tab Tab Tab Return
    sleep 2
    shot "$1"
}

# The performance view (issue 28): a four-cue set list loaded with the keyboard (Stage... >
# Load set list..., the file named in JUCE's own file dialog), the view, then n n: cue 3 of 4.
performance_shot() {
    cat > "$home/show.json" <<'JSON'
{"armadillo_setlist": 1,
 "cues": [
  {"name": "Intro", "scene": "theremin"},
  {"name": "Gestures", "scene": "sound-design"},
  {"name": "Wide", "scene": "theremin", "parameters": {"theremin.range": 24, "theremin.scale": "minor pentatonic"}},
  {"name": "Over the piano", "scene": "layered-keyboard"}
 ]}
JSON
    key shift+Tab shift+Tab Return     # from Help, past Setup, to Stage...: its menu
    key Down Down Return               # Load set list...
    sleep 1.5
    # JUCE's own dialog (no zenity here) opens in the home folder, where show.json is; its "file:" field, clicked
    # (the window sits at 0,0 with a fixed size, so the dialog's place is fixed), takes the path.
    xdotool mousemove 690 570 click 1; sleep 0.3
    xdotool mousemove 2900 2000
    type_text "show.json"
    key Return
    sleep 2
    # No window manager: the closed dialog leaves no window focused, so a click on Stage...
    # gives the app the keyboard back; the menu's first item opens the view.
    xdotool mousemove 1123 83 click 1; sleep 0.5
    xdotool mousemove 2900 2000
    key Down Return
    key n n   # cue 3 of 4: a theremin, so the motors show levels
    sleep 1
    shot app-performance-view
}
if [ "${ARMADILLO_SHOTS:-}" = performance ]; then
    start_app 1
    size 1366 768
    key Escape
    performance_shot
    stop_app
    echo "done: $out"
    exit 0
fi

# 1. First run, laptop size: the welcome, then the app behind it (no device, no sound card).
start_app 1
size 1366 768
shot app-welcome
key Escape
shot app-first-run
# 2. The minimum size (720x520): main view, the welcome, a device calibration-free panel set.
size 720 520
shot app-minimum
key F1
shot app-minimum-welcome
key Escape
# 3. Keyboard-only braille training: Tab to Preset, open it, pick "Braille: training".
size 1366 768
xdotool mousemove 2900 2000
key shift+Tab shift+Tab shift+Tab shift+Tab shift+Tab shift+Tab   # closing the welcome left the focus on Help: back to Preset (past Setup, Stage, Mapping, Reader, Wander)
key Return                 # opens the preset list
key Down Down Down Down Down Down Down Down Down Return
sleep 2
shot app-training-start
for answer in lefy; do type_text "$answer"; key Return; done
shot app-training-typo
key ctrl+a BackSpace
type_text left; key Return
sleep 1
type_text right; key Return
sleep 1
key F6
sleep 1
shot app-training-feedback
key Escape
shot app-training-escaped
# Back into the panel with Tab (Scene, Preset, Wander, Reader, Mapping, Stage, Setup, Help, About,
# the message and its OK when one shows, arm view, the panel),
# then the whole training, answered from the prompts the app writes to stderr (as a screen reader
# following the terminal hears them): keyboard only, to "Training complete".
key Tab Tab Tab Tab Tab Tab Tab Tab Tab Tab Tab Tab Tab
for _ in $(seq 80); do
    last=$(grep -a "ARMadillo training:" "$home/app.log" | tail -1 || true)
    case "$last" in *"Training complete"*) break ;; esac
    case "$last" in
        *"left, right or both?") answer=both ;;
        *"and hold it"*) answer=here ;;
        *"which letter?") answer=e ;;
        *"read the alphabet") answer=abcdefghijklmnopqrstuvwxyz ;;
        *"which word?") answer=exit ;;
        *) answer=both ;;
    esac
    type_text "$answer"
    key Return
    sleep 0.5
done
sleep 1
shot app-training-complete
key F8
size 720 520
calibration_shot app-minimum-calibration
stop_app
# 3b. The performance view, laptop size.
start_app 1
size 1366 768
key Escape
performance_shot
stop_app

# 4. 200 % scale at the minimum logical size (1440x1040 pixels), with the training panel.
start_app 2
size 1440 1040
shot app-200-welcome
key Escape; sleep 1; key Escape   # (the first may come before the window has the keyboard)
shot app-200-minimum
key shift+Tab shift+Tab shift+Tab shift+Tab shift+Tab shift+Tab Return Down Down Down Down Down Down Down Down Down Return
sleep 2
shot app-200-training
key F8
calibration_shot app-200-calibration
stop_app
echo "done: $out"
