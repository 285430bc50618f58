#!/usr/bin/env bash
# The core test suite under the sanitizers, each in its own build directory:
#   build-asan  AddressSanitizer + UndefinedBehaviorSanitizer, every core test (ctest)
#   build-tsan  ThreadSanitizer, the tests that run threads (queues, device link and pty,
#               simulator, OSC, live session, sound card, the real-time scene tests)
# The JUCE plugin is left out (-DARMADILLO_BUILD_PLUGIN=OFF): the sanitizers cover the core it
# links. The real-time guard steps aside under the sanitizers (they own malloc/operator new); its
# tests say so with a warning. Usage: scripts/sanitize.sh [asan|tsan|all] (default all).
# Fails when a build fails or a sanitizer reports anything.
set -euo pipefail
cd "$(dirname "$0")/.."
which="${1:-all}"
jobs="${JOBS:-2}"
common=(-G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DARMADILLO_BUILD_PLUGIN=OFF -DARMADILLO_BUILD_BENCHMARKS=OFF)

run_asan() {
    cmake -S . -B build-asan "${common[@]}" \
        -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined" \
        -DCMAKE_C_FLAGS="-fsanitize=address,undefined -fno-omit-frame-pointer" \
        -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined"
    cmake --build build-asan -j"$jobs"
    ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1" \
    UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
        ctest --test-dir build-asan --output-on-failure --timeout 1800 -j"$jobs"
}

run_tsan() {
    cmake -S . -B build-tsan "${common[@]}" \
        -DCMAKE_CXX_FLAGS="-fsanitize=thread -fno-omit-frame-pointer" \
        -DCMAKE_C_FLAGS="-fsanitize=thread -fno-omit-frame-pointer" \
        -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread"
    cmake --build build-tsan -j"$jobs" --target tests_core tests_device tests_live tests_live_realtime tests_audio tests_instruments armadillo
    # setarch -R: TSan's shadow memory needs the address layout without ASLR on recent kernels.
    TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1" \
        setarch "$(uname -m)" -R ctest --test-dir build-tsan --output-on-failure --timeout 1800 -j"$jobs" \
        -R '^(core|device|live|live_realtime|audio|instruments)$'
}

case "$which" in
    asan) run_asan ;;
    tsan) run_tsan ;;
    all) run_asan; run_tsan ;;
    *) echo "usage: $0 [asan|tsan|all]" >&2; exit 2 ;;
esac
echo "sanitize.sh: clean ($which)"
