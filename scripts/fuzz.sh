#!/usr/bin/env bash
# Coverage-guided fuzzing of every parser (docs/SECURITY.md "Fuzzing"): builds the libFuzzer
# targets of Tests/Fuzz/ with clang, AddressSanitizer and UndefinedBehaviorSanitizer into
# ./build-fuzz, then runs each for SECONDS, one at a time.
#   bash scripts/fuzz.sh SECONDS [TARGET…]     (default: every target; FUZZ_JOBS=N builds with N jobs)
# Each target starts from its seeds (Tests/Fuzz/corpus/<target>/ and Tests/Fuzz/regressions/<target>/),
# copied into build-fuzz/corpus/<target>/, which keeps what the fuzzer adds between runs (never the
# repository's seeds). One line per target, then `fuzz: T targets, R runs, C crashes`. A crash,
# sanitizer report, hang (-timeout) or running out of memory (-rss_limit_mb) is a finding: its
# input is kept under build-fuzz/findings/<target>/ and named, and the script exits 1. A fixed
# finding's input goes to Tests/Fuzz/regressions/<target>/ (replayed by tests_fuzz_regressions).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ] || ! [[ "$1" =~ ^[0-9]+$ ]]; then
    echo "usage: $0 SECONDS [TARGET...]" >&2
    exit 2
fi
seconds="$1"
shift
root="$PWD"
build="$root/build-fuzz"
jobs="${FUZZ_JOBS:-2}"

mkdir -p "$build"
launcher=()
if command -v ccache > /dev/null; then
    export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
    launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
# The core rooms the targets link, instrumented; -O1 with assertions on (no NDEBUG).
CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja "${launcher[@]}" \
    -DARMADILLO_FUZZ=ON -DARMADILLO_BUILD_PLUGIN=OFF -DARMADILLO_BUILD_TESTS=OFF \
    -DARMADILLO_BUILD_BENCHMARKS=OFF -DARMADILLO_BUILD_FIRMWARE=OFF \
    -DCMAKE_BUILD_TYPE=Fuzz -DCMAKE_CXX_FLAGS_FUZZ=-O1 -DCMAKE_C_FLAGS_FUZZ=-O1 > "$build/configure.log" 2>&1 \
    || { cat "$build/configure.log" >&2; exit 1; }
cmake --build "$build" -j "$jobs" --target fuzz_all > "$build/build.log" 2>&1 \
    || { tail -n 60 "$build/build.log" >&2; echo "fuzz: the build failed (log: $build/build.log)" >&2; exit 1; }

targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    for f in Tests/Fuzz/fuzz_*.cpp; do
        n="${f##*/fuzz_}"
        targets+=("${n%.cpp}")
    done
fi

export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:allocator_may_return_null=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$root/scripts/lsan.supp:print_suppressions=0}"

total_runs=0
crashes=0
for t in "${targets[@]}"; do
    exe="$build/fuzz/fuzz_$t"
    if [ ! -x "$exe" ]; then
        echo "fuzz: no target '$t' (Tests/Fuzz/fuzz_$t.cpp and its line in Tests/Fuzz/CMakeLists.txt)" >&2
        exit 2
    fi
    corpus="$build/corpus/$t"
    findings="$build/findings/$t"
    mkdir -p "$corpus" "$findings"
    for seeds in "Tests/Fuzz/corpus/$t" "Tests/Fuzz/regressions/$t"; do
        if [ -d "$seeds" ]; then cp -n "$seeds"/* "$corpus"/ 2>/dev/null || true; fi
    done
    log="$findings/last-run.log"
    rc=0
    ( cd "$findings" && "$exe" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
        -max_len=65536 -len_control=200 -print_final_stats=1 -artifact_prefix="$findings/" "$corpus" ) > "$log" 2>&1 || rc=$?
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    runs=${runs:-0}
    status=$(grep -E '^#[0-9]+' "$log" | tail -n 1 || true)
    cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<< "$status")
    ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<< "$status")
    units=$(find "$corpus" -type f | wc -l)
    total_runs=$((total_runs + runs))
    if [ "$rc" -eq 0 ]; then
        result="ok"
    else
        crashes=$((crashes + 1))
        artifact=$(grep -o "Test unit written to [^ ]*" "$log" | tail -n 1 | sed 's/Test unit written to //')
        kind=$(grep -m1 -oE 'ERROR: (AddressSanitizer|UndefinedBehaviorSanitizer|LeakSanitizer|libFuzzer): [a-zA-Z-]+|runtime error: .*' "$log" || echo "exit $rc")
        result="FINDING: $kind; input ${artifact:-(none written)}; log $log"
    fi
    printf 'fuzz_%-16s %10s runs  cov %-6s ft %-6s corpus %-5s %s\n' "$t" "$runs" "${cov:-?}" "${ft:-?}" "$units" "$result"
done
echo "fuzz: ${#targets[@]} targets, $total_runs runs, $crashes crashes"
[ "$crashes" -eq 0 ]
