#!/usr/bin/env bash
# The test suite under the sanitizers, each in its own build directory:
#   build-asan  AddressSanitizer + UndefinedBehaviorSanitizer, the whole suite (ctest), the JUCE
#               plugin and its host test included (ARMADILLO_NO_PLUGIN=1 leaves them out)
#   build-tsan  ThreadSanitizer, the tests that run threads (queues, device link and pty,
#               simulator, OSC, live session, sound card, the real-time scene tests)
# The real-time guard steps aside under the sanitizers (they own malloc/operator new); its tests
# say so with a warning. Usage: scripts/sanitize.sh [asan|tsan|all] (default all).
# Fails when a build fails or a sanitizer reports anything.
set -euo pipefail
cd "$(dirname "$0")/.."
which="${1:-all}"
jobs="${JOBS:-2}"
common=(-G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DARMADILLO_BUILD_BENCHMARKS=OFF)
plugin=ON
# ccache (when installed) as in build.sh: a second sanitizer build of another checkout reuses it.
# These builds carry debug info (-g), for which ccache also hashes the working directory unless
# told not to: without CCACHE_NOHASHDIR a fresh clone missed every object (measured: 7 s per
# object instead of a hit). The price: a report's source paths may name the checkout that filled
# the cache (the same files).
if command -v ccache > /dev/null; then
    export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"
    export CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
    common+=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
if [ "${ARMADILLO_NO_PLUGIN:-0}" = "1" ]; then plugin=OFF; fi

run_asan() {
    cmake -S . -B build-asan "${common[@]}" -DARMADILLO_BUILD_PLUGIN=$plugin \
        -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined" \
        -DCMAKE_C_FLAGS="-fsanitize=address,undefined -fno-omit-frame-pointer" \
        -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
        -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" \
        -DCMAKE_MODULE_LINKER_FLAGS="-fsanitize=address,undefined"
    cmake --build build-asan -j"$jobs"
    LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0" \
    ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1" \
    UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
        ctest --test-dir build-asan --output-on-failure --timeout 1800 -j"$jobs"
}

run_tsan() {
    cmake -S . -B build-tsan "${common[@]}" -DARMADILLO_BUILD_PLUGIN=OFF \
        -DCMAKE_CXX_FLAGS="-fsanitize=thread -fno-omit-frame-pointer" \
        -DCMAKE_C_FLAGS="-fsanitize=thread -fno-omit-frame-pointer" \
        -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread"
    cmake --build build-tsan -j"$jobs" --target tests_core tests_link tests_osc tests_live tests_live_realtime tests_audio tests_instruments armadillo
    # setarch -R: TSan's shadow memory needs the address layout without ASLR on recent kernels.
    TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1" \
        setarch "$(uname -m)" -R ctest --test-dir build-tsan --output-on-failure --timeout 1800 -j"$jobs" \
        -R '^(core|link|osc|live|live_realtime|audio|instruments)$'
}

case "$which" in
    asan) run_asan ;;
    tsan) run_tsan ;;
    all) run_asan; run_tsan ;;
    *) echo "usage: $0 [asan|tsan|all]" >&2; exit 2 ;;
esac
echo "sanitize.sh: clean ($which)"
