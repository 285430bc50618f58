#!/usr/bin/env python3
"""Draws docs/images/wiring-mega2560.svg, the reference board's wiring diagram (docs/HARDWARE.md).

Plain Python (standard library only): the SVG is written by hand so the drawing needs nothing to
be installed. Run from anywhere: python3 scripts/draw-wiring.py [OUT.svg]
"""
import os
import sys

W, H = 1100, 720
out = []


def rect(x, y, w, h, fill, label=None, sub=None):
    out.append(f'<rect x="{x}" y="{y}" width="{w}" height="{h}" rx="8" fill="{fill}" stroke="#222" stroke-width="2"/>')
    if label:
        out.append(f'<text x="{x + w / 2}" y="{y + 24}" text-anchor="middle" font-size="17" font-weight="bold">{label}</text>')
    if sub:
        for i, line in enumerate(sub.split("\n")):
            out.append(f'<text x="{x + w / 2}" y="{y + 44 + 16 * i}" text-anchor="middle" font-size="12">{line}</text>')


def text(x, y, s, size=12, anchor="start", color="#222"):
    out.append(f'<text x="{x}" y="{y}" font-size="{size}" text-anchor="{anchor}" fill="{color}">{s}</text>')


def wire(points, color, width=2.5, dash=None):
    d = " ".join(f"{x},{y}" for x, y in points)
    extra = f' stroke-dasharray="{dash}"' if dash else ""
    out.append(f'<polyline points="{d}" fill="none" stroke="{color}" stroke-width="{width}"{extra}/>')


def dot(x, y, color="#222"):
    out.append(f'<circle cx="{x}" cy="{y}" r="4" fill="{color}"/>')


# Blocks
rect(420, 150, 200, 430, "#e8f0ff", "Arduino Mega 2560", "ATmega2560, 16 MHz\n5 V logic")
rect(40, 150, 200, 120, "#fff4d6", "MPU-9250 breakout", "GY-9250 / equivalent\naccel + gyro + AK8963 mag")
rect(40, 330, 200, 110, "#e9ffe9", "HC-05 Bluetooth", "57 600 baud, 8N1\n(or the Mega's USB port)")
rect(690, 150, 170, 430, "#ffe9e9", "ULN2803A", "8 Darlington sinks\n+ internal flyback diodes\n(9th motor: 2nd ULN2803A\nor one NPN + 1N4148)")
rect(900, 150, 180, 430, "#f4f4f4", "9 ERM motors", "3 V rated, 10 mm coin\nk = 3·row + col + 1")
rect(690, 620, 380, 70, "#fff0f0", "Motor supply 5–9 V (own battery)", "+ → every motor's red lead; − → ULN2803 GND (pin 9)")
rect(40, 500, 240, 110, "#f0f0ff", "Logic supply", "USB 5 V or 7–12 V into the\nMega's barrel jack / VIN")

# I2C + power to the IMU
wire([(240, 190), (420, 190)], "#1f77b4"); text(250, 184, "SDA → D20 (SDA)")
wire([(240, 215), (420, 215)], "#ff7f0e"); text(250, 209, "SCL → D21 (SCL)")
wire([(240, 240), (420, 240)], "#d62728"); text(250, 234, "VCC → 3.3 V")
wire([(240, 262), (420, 262)], "#222"); text(250, 257, "GND → GND")
text(40, 292, "Breakout with on-board 3.3 V regulator and", 11)
text(40, 306, "I2C level shifting (most GY-9250 boards); AD0 low → 0x68", 11)

# Serial
wire([(240, 365), (420, 365)], "#2ca02c"); text(250, 359, "TXD → D0 (RX0)")
wire([(240, 390), (420, 390)], "#9467bd"); text(250, 384, "RXD ← D1 (TX0) via 1k/2k divider")
wire([(240, 412), (420, 412)], "#d62728"); text(250, 407, "VCC → 5 V, GND → GND")

# Logic power
wire([(280, 555), (420, 555)], "#d62728"); text(284, 548, "5 V / VIN")

# PWM pins → ULN inputs
pins = [("D5", "OC3A", 1), ("D2", "OC3B", 2), ("D3", "OC3C", 3), ("D6", "OC4A", 4), ("D7", "OC4B", 5),
        ("D8", "OC4C", 6), ("D46", "OC5A", 7), ("D45", "OC5B", 8), ("D44", "OC5C", 9)]
for i, (pin, oc, k) in enumerate(pins):
    y = 290 + i * 30
    wire([(620, y), (690, y)], "#8c564b")
    text(624, y - 4, f"{pin}", 11)
    wire([(860, y), (900, y)], "#444")
    text(905, y + 4, f"motor {k} (−)", 11)
    dot(690, y)
text(555, 276, "PWM 20.5 kHz, duty = level/15 →", 11, "end", "#8c564b")
for i, (pin, oc, k) in enumerate(pins):
    text(612, 294 + i * 30, oc, 10, "end", "#555")

# Grounds and motor supply
wire([(620, 560), (650, 560), (650, 600), (745, 600), (745, 580)], "#222", 3)
text(560, 575, "GND (common)", 11)
wire([(1000, 620), (1000, 580)], "#d62728", 3)
text(1006, 605, "+V motor", 11, color="#d62728")
wire([(775, 620), (775, 580)], "#d62728", 2, "6,4")
text(700, 612, "COM (pin 10) → +V", 11, color="#d62728")

text(W / 2, 40, "ARMadillo reference board — wiring", 22, "middle")
text(W / 2, 64, "Motors never run from the Arduino's 5 V; logic and motor grounds meet at the ULN2803.", 13, "middle")
text(W / 2, 84, "Board flat on the back of the forearm, MPU-9250 x arrow toward the hand, chip side up (INTERFACES.md frame).", 13, "middle")
text(W / 2, 104, "Drawn by scripts/draw-wiring.py", 11, "middle", "#777")

svg = (f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" '
       f'font-family="DejaVu Sans, Arial, sans-serif">\n<rect width="{W}" height="{H}" fill="white"/>\n'
       + "\n".join(out) + "\n</svg>\n")
target = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "docs", "images", "wiring-mega2560.svg")
with open(target, "w", encoding="utf-8") as f:
    f.write(svg)
print(f"draw-wiring: wrote {os.path.normpath(target)}")
