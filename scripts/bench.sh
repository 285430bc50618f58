#!/usr/bin/env bash
# Runs every benchmark once and prints its numbers (no pass/fail on time): every bench_* built
# under build/Benchmarks (fusion, device, tactile, follow — the score follower per audio block —,
# instruments, live, plugin). Build first
# (scripts/build.sh). docs/BENCHMARKS.md says what each one measures.
set -uo pipefail
cd "$(dirname "$0")/.."
status=0
for b in $(find build/Benchmarks -maxdepth 3 -type f -name 'bench_*' -perm -u+x | sort); do
    echo "=== $(basename "$b")"
    "$b" || status=1
done
if [ -x scripts/score-broad.sh ] && [ -d ../shared/data/broad-dev ]; then
    echo "=== BROAD orientation accuracy (armadillo fuse)"
    bash scripts/score-broad.sh build/bin/armadillo || status=1
    echo "=== orientation through dropouts (armadillo fuse and VQF on BROAD with gaps cut out)"
    python3 scripts/bench_gaps.py --armadillo build/bin/armadillo || status=1
fi
exit $status
