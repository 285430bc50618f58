#!/usr/bin/env python3
"""Plays every scene of an installed ARMadillo VST3 through a third-party host (pedalboard).

    python3 play_scenes.py /usr/lib/vst3/ARMadillo.vst3 [EXPECTED_VERSION]

For each scene the orientation is automated (source = host automation) between blocks, as a
DAW's automation lane would; the audio is measured, and the motor levels the plugin sends over
its OSC output (/armadillo/motors, to a UDP port of this script) are counted. The score scene
is played with both shipped scores, chosen through the plugin's state (its `score` setting).
pedalboard gives the plugin no playing transport (a VST3 host without a play head sends a
stopped one), and a score follows the transport, so here a score must stay silent: that it
loads and keeps its motors off is what is checked (Tests/Plugin/HostScenes.cpp plays the scores
under JUCE's host with a playing transport). Prints one line per run and exits 1 when a scene
that must sound is silent or any level leaves 0..15.
"""
import math
import re
import socket
import struct
import sys
import time

import numpy as np
import pedalboard

RATE = 48000
BLOCK = 960            # 20 ms per call; the orientation changes between calls
SOUNDING = {"theremin", "sound-design"}   # scenes whose sound this slow movement must bring


def osc_motors(packet):
    """Levels of one /armadillo/motors message (i×N), or None for any other packet."""
    if not packet.startswith(b"/armadillo/motors\x00"):
        return None
    end = packet.index(b",", 18)
    tags_end = packet.index(b"\x00", end)
    count = tags_end - end - 1
    offset = (tags_end + 4) & ~3
    return struct.unpack(">%di" % count, packet[offset:offset + 4 * count])


JUCE_B64 = ".ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+"


def juce_b64_decode(text):
    """JUCE's MemoryBlock::fromBase64Encoding: "<size>.<chars>", 6 bits a char, least significant first."""
    size, chars = text.split(".", 1)
    out = bytearray(int(size))
    for i, c in enumerate(chars):
        v = JUCE_B64.index(c)
        for b in range(6):
            bit = i * 6 + b
            if bit < 8 * len(out) and (v >> b) & 1:
                out[bit // 8] |= 1 << (bit % 8)
    return bytes(out)


def juce_b64_encode(data):
    chars = []
    for i in range((len(data) * 8 + 5) // 6):
        v = 0
        for b in range(6):
            bit = i * 6 + b
            if bit < 8 * len(data) and (data[bit // 8] >> (bit % 8)) & 1:
                v |= 1 << b
        chars.append(JUCE_B64[v])
    return "%d.%s" % (len(data), "".join(chars))


def set_state(plugin, port, score):
    """Writes oscOut* and score into the plugin's own state (docs/PLUGIN.md "State"), which the
    host keeps inside JUCE's VST3 state document: binary XML <VST3PluginState><IComponent>."""
    state = plugin.raw_state
    text = state[8:8 + struct.unpack("<I", state[4:8])[0]].decode("utf-8").rstrip("\x00")
    component = re.search(r"<IComponent>([^<]*)</IComponent>", text).group(1)
    inner = juce_b64_decode(component)
    xml_size = struct.unpack("<I", inner[4:8])[0]
    xml = inner[8:8 + xml_size].decode("utf-8").rstrip("\x00")
    rest = inner[8 + xml_size:]          # the VST3 wrapper's private trailer, kept as it is
    for key, value in (("oscOutEnabled", "1"), ("oscOutHost", "127.0.0.1"), ("oscOutPort", str(port)),
                       ("score", score)):
        xml, n = re.subn(r'%s="[^"]*"' % key, '%s="%s"' % (key, value), xml)
        if n != 1:
            raise SystemExit("the plugin's state has no setting '%s'" % key)
    body = xml.encode("utf-8") + b"\x00"
    inner = inner[:4] + struct.pack("<I", len(body)) + body + rest
    text = text.replace(component, juce_b64_encode(inner))
    body = text.encode("utf-8") + b"\x00"
    plugin.raw_state = state[:4] + struct.pack("<I", len(body)) + body


def main():
    path = sys.argv[1]
    plugin = pedalboard.load_plugin(path)
    print("host: pedalboard %s loaded %s: '%s' version %s, instrument=%s"
          % (pedalboard.__version__, path, plugin.name, plugin.version, plugin.is_instrument))
    failed = False
    if len(sys.argv) > 2 and plugin.version != sys.argv[2]:
        print("FAIL: the plugin reports version %s, expected %s" % (plugin.version, sys.argv[2]))
        failed = True
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", 0))
    sock.setblocking(False)
    port = sock.getsockname()[1]
    scenes = plugin.parameters["scene"].valid_values
    runs = [(s, None) for s in scenes if s != "score"] + [("score", "rite-of-spring"), ("score", "polytope")]
    for scene, score in runs:
        set_state(plugin, port, score or "rite-of-spring")
        plugin.source = "host automation"
        plugin.scene = scene
        plugin.reset()
        while True:   # drop what the previous run sent
            try:
                sock.recv(2048)
            except BlockingIOError:
                break
        audio, motors = [], []
        seconds = 8.0
        for i in range(int(seconds * RATE / BLOCK)):
            t = i * BLOCK / RATE
            plugin.elevation = 40.0 * math.sin(2 * math.pi * t / 4.0)
            plugin.azimuth = (20.0 * math.sin(2 * math.pi * t / 6.0)) % 360.0
            plugin.roll = 70.0 * math.sin(2 * math.pi * t / 1.5)
            out = plugin([], duration=BLOCK / RATE, sample_rate=RATE, num_channels=2, reset=False)
            audio.append(out)
            time.sleep(BLOCK / RATE)   # the plugin's control clock runs in real time between blocks
            while True:
                try:
                    m = osc_motors(sock.recv(2048))
                except BlockingIOError:
                    break
                if m is not None:
                    motors.append(m)
        audio = np.concatenate(audio, axis=1)
        rms = float(np.sqrt(np.mean(audio ** 2)))
        finite = bool(np.all(np.isfinite(audio)))
        moving = sum(1 for m in motors if any(m))
        peak = max((max(m) for m in motors), default=0)
        name = scene + (" (%s)" % score if score else "")
        ok = finite and (scene not in SOUNDING or rms > 1e-3) and (scene != "score" or moving == 0) and peak <= 15
        print("%-4s %-28s audio rms %.4f, %d motor messages, %d with a motor on, highest level %d"
              % ("ok" if ok else "FAIL", name, rms, len(motors), moving, peak))
        failed = failed or not ok
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
