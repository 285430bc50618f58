#!/usr/bin/env bash
# Installs what ARMadillo builds and tests with, from Debian's packages. Idempotent: does nothing
# when all is there; uses sudo only when not already root.
#   --packaging   also what scripts/package.sh and scripts/check-package.sh use
#                 (lintian, debootstrap, desktop-file-utils)
set -euo pipefail

packages=(
    # toolchain
    build-essential cmake ninja-build pkg-config git
    # compiler cache for repeated builds (-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    ccache
    # fuzzing (scripts/fuzz.sh, docs/SECURITY.md): clang, its libFuzzer and sanitizer runtimes
    clang libclang-rt-14-dev
    # the core: Eigen, serial ports, braille tables, tests
    libeigen3-dev libserialport-dev liblouis-dev liblouis-data catch2
    # a reader alone (docs/ACCESSIBILITY.md): speech-dispatcher and BrlAPI, loaded at run time (dlopen);
    # espeak-ng, speech-dispatcher and brltty for the manual checks there
    libspeechd-dev libbrlapi-dev espeak-ng speech-dispatcher speech-dispatcher-espeak-ng brltty
    # walking navigation (docs/NAVIGATION.md): GPX routes, gpsd positions; gpsd + gpsfake for its tests
    libpugixml-dev libgps-dev gpsd gpsd-clients
    # audio files (WAV/RF64 out; WAV, AIFF, FLAC, Ogg in) and resampling of user recordings
    libsndfile1-dev libsamplerate0-dev
    # MQTT (docs/MQTT.md): the client library; the broker its tests start on loopback, and its clients
    libmosquitto-dev mosquitto mosquitto-clients
    # the live instrument as a web page (issue 47): its HTTP server, the address as a QR code; the
    # browser tests drive Debian's Chromium headless through chromium-driver and Selenium
    # (axe-core, which Debian does not package, comes from npm at test time: Tests/Web/README.md)
    libcpp-httplib-dev libqrencode-dev chromium chromium-driver python3-selenium
    # JUCE 7 (Debian ships it with its CMake config) and what its modules link on Linux
    # (ALSA for the CLI's sound card too; JACK headers for the standalone app's JACK driver)
    juce-modules-source lv2-dev libasound2-dev libjack-jackd2-dev libfreetype-dev libfontconfig1-dev
    libx11-dev libxcomposite-dev libxcursor-dev libxext-dev libxinerama-dev libxrandr-dev libxrender-dev
    libgl-dev libgtk-3-dev
    # the editor's own tests (tests_plugin_ui) drive a real window under Xvfb
    xvfb xauth
    # the tactor output's tests and benchmark start their own JACK server (dummy backend; issue 33)
    jackd2
    # benchmarks' scoring scripts (scripts/bench_gaps.py, BROAD); the Pd tests' pitch measurement
    python3-numpy
    # Pure Data's [armadillo] and [armadillo~] (docs/PUREDATA.md): m_pd.h, and the pd its tests run
    puredata-core puredata-dev
    # the reference firmware (docs/HARDWARE.md): AVR toolchain and its simavr loop test
    gcc-avr avr-libc binutils-avr simavr libsimavr-dev libelf-dev
)
if [ "${1:-}" = "--packaging" ]; then
    packages+=(lintian debootstrap desktop-file-utils dpkg-dev file)
fi

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
    echo "install-deps: all ${#packages[@]} packages present"
    exit 0
fi

run=()
if [ "$(id -u)" -ne 0 ]; then
    if ! command -v sudo > /dev/null; then
        echo "install-deps: these Debian packages are missing: ${missing[*]}" >&2
        echo "install-deps: you are not root and 'sudo' is not installed. Either run this script as root" >&2
        echo "  (su -c 'bash scripts/install-deps.sh'), or install sudo and add yourself to the 'sudo' group" >&2
        echo "  (as root: apt-get install sudo && adduser $(id -un) sudo; then log in again)." >&2
        exit 1
    fi
    run=(sudo)
fi
echo "install-deps: installing ${missing[*]}"
# env inside sudo: sudo's env_reset would drop a DEBIAN_FRONTEND set before it.
"${run[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq
"${run[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
