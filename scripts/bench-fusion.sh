#!/usr/bin/env bash
# Runs bench_fusion and, if the `vqf` Python package is installed (pip install vqf), times VQF's
# offline filter on the same IMU file in the same run and prints the ratio of per-sample costs.
#   scripts/bench-fusion.sh [BENCH_BINARY] [IMU.csv.gz]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bench="${1:-$here/build/bin/bench_fusion}"
[[ -x "$bench" ]] || bench="$here/build/Benchmarks/Fusion/bench_fusion"
gz="${2:-$here/../shared/data/broad-dev/07_undisturbed_fast_rotation_B_imu.csv.gz}"
[[ -x "$bench" ]] || { echo "bench-fusion: no bench_fusion binary (pass its path)" >&2; exit 2; }
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
gzip -dc "$gz" > "$tmp/imu.csv"
out="$("$bench" "$tmp/imu.csv")"
echo "$out"
ours="$(sed -n 's/^ARMADILLO_US_PER_UPDATE=//p' <<<"$out")"
python3 - "$tmp/imu.csv" "$ours" <<'PY'
import sys, time
try:
    import numpy as np
    from vqf import VQF, offlineVQF
except ImportError:
    print("vqf not installed (pip install vqf): no comparison"); sys.exit(0)
d = np.loadtxt(sys.argv[1], delimiter=',', skiprows=1)
gyr, acc, mag = (np.ascontiguousarray(d[:, i:i + 3]) for i in (1, 4, 7))
Ts = float(np.median(np.diff(d[:, 0])))
best = 1e300
for _ in range(5):
    t0 = time.perf_counter(); offlineVQF(gyr, acc, mag, Ts, {}); best = min(best, time.perf_counter() - t0)
us_off = best / len(d) * 1e6
best = 1e300
for _ in range(3):
    v = VQF(Ts); t0 = time.perf_counter(); v.updateBatch(gyr, acc, mag); best = min(best, time.perf_counter() - t0)
us_batch = best / len(d) * 1e6
ours = float(sys.argv[2])
print(f"VQF offlineVQF (C++ core, forward+backward bias pass): {us_off:.3f} us per sample")
print(f"VQF real-time updateBatch (C++ core):                   {us_batch:.3f} us per sample")
print(f"ratio ARMADILLO SR-UKF / VQF real-time: {ours / us_batch:.1f}x   (/ offline: {ours / us_off:.1f}x)")
PY
