#!/usr/bin/env bash
# Installs everything ARMadillo builds and tests with, from Debian's packages. Idempotent: does
# nothing when all is there; uses sudo only when not already root.
set -euo pipefail

packages=(
    # toolchain
    build-essential cmake ninja-build pkg-config git
    # the core: Eigen, serial ports, braille tables, tests
    libeigen3-dev libserialport-dev liblouis-dev liblouis-data catch2
    # JUCE 7 (Debian ships it with its CMake config) and what its modules link on Linux
    juce-modules-source lv2-dev libasound2-dev libjack-jackd2-dev libfreetype-dev libfontconfig1-dev
    libx11-dev libxcomposite-dev libxcursor-dev libxext-dev libxinerama-dev libxrandr-dev libxrender-dev
    libgl-dev libgtk-3-dev
    # tests: pseudo-terminals, headless display for the app, BROAD scoring
    socat xvfb xauth python3-numpy
    # the reference firmware (docs/HARDWARE.md): AVR toolchain, flashing, and its simavr loop test
    gcc-avr avr-libc binutils-avr avrdude simavr libsimavr-dev libelf-dev
)

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
    echo "install-deps: all ${#packages[@]} packages present"
    exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
