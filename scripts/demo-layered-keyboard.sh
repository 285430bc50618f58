#!/usr/bin/env bash
# Demonstration of the layered-keyboard scene (thesis §5.2, docs/INSTRUMENTS.md): a synthesised
# piano phrase (C4 E4 G4 C5, then a C-major chord) is the audio input; the arm rests on the keys
# while it plays, then rises through the five captured layers (elevation 0°…60°), turns right on
# the last one (pitch shift) and rolls (filter). Writes into OUTDIR (default /tmp/layered-demo):
#   piano.wav   the phrase the scene listens to
#   motion.csv  the arm (pose file: t,elevation,azimuth,roll)
#   layered.wav what the scene plays
#   piano.mid   the same phrase as MIDI notes (what a digital piano's MIDI out would send)
#   layered-midi.wav  what the scene plays when it takes its notes from piano.mid (--midi-in)
# and the captured notes of both renders are printed by `armadillo render` on stderr.
# Usage: scripts/demo-layered-keyboard.sh [ARMADILLO_BINARY] [OUTDIR]
set -euo pipefail
bin=${1:-build/bin/armadillo}
out=${2:-/tmp/layered-demo}
mkdir -p "$out"
python3 - "$out" <<'EOF'
import math, struct, sys, wave
out = sys.argv[1]
fs = 48000
x = [0.0] * int(4.0 * fs)
def tone(onset, midi, amp):
    f0 = 440.0 * 2 ** ((midi - 69) / 12)
    start = int(onset * fs)
    for i in range(start, min(len(x), start + int(3.0 * fs))):
        t = (i - start) / fs
        v = 0.0
        for h in range(1, 9):
            f = h * f0 * math.sqrt(1 + 2e-4 * h * h)
            if f > 0.45 * fs:
                break
            v += math.exp(-t * (1 + 0.3 * (h - 1)) / 0.5) * math.sin(2 * math.pi * f * t) / h
        x[i] += amp * min(1.0, t / 0.002) * v
for k, m in enumerate([60, 64, 67, 72]):
    tone(0.2 + 0.5 * k, m, 0.25)
for m in [60, 64, 67]:
    tone(2.2, m, 0.12)
with wave.open(out + "/piano.wav", "wb") as w:
    w.setnchannels(1); w.setsampwidth(2); w.setframerate(fs)
    w.writeframes(b"".join(struct.pack("<h", int(max(-1, min(1, v)) * 32767)) for v in x))
# The same notes as a Standard MIDI File (format 0, 480 ticks per quarter at 120 bpm: 960 per s).
notes = [(0.2 + 0.5 * k, 0.45, m) for k, m in enumerate([60, 64, 67, 72])] + [(2.2, 1.0, m) for m in [60, 64, 67]]
events = sorted([(round(t * 960), 1, m) for t, d, m in notes] + [(round((t + d) * 960), 0, m) for t, d, m in notes])
def vlq(v):
    b = [v & 0x7F]
    v >>= 7
    while v:
        b.insert(0, (v & 0x7F) | 0x80)
        v >>= 7
    return bytes(b)
track, now = b"", 0
for tick, on, m in events:
    track += vlq(tick - now) + bytes([0x90, m, 90 if on else 0])
    now = tick
track += b"\x00\xff\x2f\x00"
with open(out + "/piano.mid", "wb") as f:
    f.write(b"MThd" + struct.pack(">IHHH", 6, 0, 1, 480) + b"MTrk" + struct.pack(">I", len(track)) + track)
# The arm: on the keys (-20°) until 3.2 s, then 1.2 s in each of the five layers (bands of 12°
# from 0° to 60°), a turn of +30° azimuth and a roll sweep on the last, then back down.
rows = ["t,elevation,azimuth,roll"]
for i in range(int(11.0 * 200) + 1):
    t = i / 200
    el, az, roll = -20.0, 10.0, 0.0
    if 3.2 <= t < 9.2:
        k = int((t - 3.2) / 1.2)
        el = 6.0 + 12.0 * k
        if k == 4:
            u = (t - 8.0) / 1.2
            az = 10.0 + 30.0 * u
            roll = -90.0 + 180.0 * u
    rows.append(f"{t:.3f},{el:.2f},{az:.2f},{roll:.2f}")
open(out + "/motion.csv", "w").write("\n".join(rows) + "\n")
EOF
"$bin" render --scene layered-keyboard --motion "$out/motion.csv" --audio-in "$out/piano.wav" \
    --out "$out/layered.wav" --tactile "$out/tactile.csv" --tail 0.5
echo "wrote $out/piano.wav, $out/motion.csv, $out/layered.wav, $out/tactile.csv" >&2
"$bin" render --scene layered-keyboard --motion "$out/motion.csv" --audio-in "$out/piano.wav" --midi-in "$out/piano.mid" \
    --out "$out/layered-midi.wav" --tail 0.5
echo "wrote $out/piano.mid, $out/layered-midi.wav (notes from MIDI)" >&2
