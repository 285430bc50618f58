#!/usr/bin/env bash
# Scores `armadillo fuse` on the BROAD trials (BROAD / VQF paper metric, ../shared/tools/score_broad.py)
# and prints a per-trial table and the mean total RMSE, with VQF (real time, `updateBatch`) and
# offline VQF (`offlineVQF`, looks ahead) scored by the same scorer in the same run beside it
# (scripts/score_vqf.py; the `vqf` PyPI package is installed like numpy if missing).
#   scripts/score-broad.sh [ARMADILLO_BINARY] [DATA_DIR]
# ARMADILLO_BINARY defaults to build/bin/armadillo; DATA_DIR to ../shared/data/broad-dev.
# Extra arguments for `armadillo fuse` can be given in FUSE_ARGS (e.g. FUSE_ARGS=--no-mag).
# Then the leave-one-trial-out cross-validation of the tuned parameters (scripts/cv_broad.py: for
# each trial, the parameters chosen on the others from a small grid score it) is printed beside the
# in-sample figure; CV_GRID overrides its grid, CV_JOBS (default 2) its parallel runs, CV=0 skips it.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${1:-$here/build/bin/armadillo}"
data="${2:-$here/../shared/data/broad-dev}"
scorer="${SCORER:-$here/../shared/tools/score_broad.py}"
[[ -x "$bin" ]] || { echo "score-broad: no armadillo binary at $bin (build it, or pass its path)" >&2; exit 2; }
[[ -d "$data" ]] || { echo "score-broad: no BROAD data at $data" >&2; exit 2; }
[[ -f "$scorer" ]] || { echo "score-broad: no scorer at $scorer" >&2; exit 2; }
if ! python3 -c 'import numpy' 2>/dev/null; then
    echo "score-broad: installing numpy for the scorer" >&2
    python3 -m pip install --quiet numpy >&2 || { echo "score-broad: numpy is needed (pip install numpy)" >&2; exit 2; }
fi
if ! python3 -c 'import vqf' 2>/dev/null; then
    echo "score-broad: installing vqf for the comparison" >&2
    python3 -m pip install --quiet vqf >&2 || { echo "score-broad: vqf is needed (pip install vqf)" >&2; exit 2; }
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
python3 "$here/scripts/score_vqf.py" "$data" "$scorer" > "$tmp/vqf.txt" \
    || { echo "score-broad: VQF comparison failed" >&2; exit 1; }
printf '%-40s %8s %8s %8s | %8s %8s %8s | %8s %8s %8s\n' trial total heading incl \
    vqf.tot vqf.head vqf.incl off.tot off.head off.incl
sum=0; n=0; vsum=0; osum=0
for imu in "$data"/*_imu.csv.gz; do
    trial="$(basename "$imu" _imu.csv.gz)"
    gzip -dc "$imu" > "$tmp/$trial.imu.csv"
    # shellcheck disable=SC2086
    "$bin" fuse --in "$tmp/$trial.imu.csv" --out "$tmp/$trial.q.csv" ${FUSE_ARGS:-} 2> "$tmp/$trial.log" \
        || { echo "score-broad: fuse failed on $trial:" >&2; cat "$tmp/$trial.log" >&2; exit 1; }
    line="$(python3 "$scorer" "$tmp/$trial.q.csv" "$data/${trial}_truth.csv.gz" --est-frame EUS)"
    tot="$(sed -n 's/.*total_rmse_deg=\([^ ]*\).*/\1/p' <<<"$line")"
    head="$(sed -n 's/.*heading_rmse_deg=\([^ ]*\).*/\1/p' <<<"$line")"
    inc="$(sed -n 's/.*inclination_rmse_deg=\([^ ]*\).*/\1/p' <<<"$line")"
    read -r _ vt vh vi ot oh oi < <(grep "^$trial " "$tmp/vqf.txt")
    printf '%-40s %8s %8s %8s | %8s %8s %8s | %8s %8s %8s\n' "$trial" "$tot" "$head" "$inc" "$vt" "$vh" "$vi" "$ot" "$oh" "$oi"
    sum="$(python3 -c "print($sum + $tot)")"; n=$((n + 1))
    vsum="$(python3 -c "print($vsum + $vt)")"; osum="$(python3 -c "print($osum + $ot)")"
done
[[ $n -gt 0 ]] || { echo "score-broad: no *_imu.csv.gz in $data" >&2; exit 2; }
printf '%-40s %8.3f %17s | %8.3f %17s | %8.3f\n' "mean total RMSE ($n trials)" "$(python3 -c "print($sum / $n)")" "" \
    "$(python3 -c "print($vsum / $n)")" "" "$(python3 -c "print($osum / $n)")"
if [[ "${CV:-1}" != "0" ]]; then
    echo
    python3 "$here/scripts/cv_broad.py" "$bin" "$data" "$scorer" --jobs "${CV_JOBS:-2}" ${CV_GRID:+--grid "$CV_GRID"} > "$tmp/cv.txt" \
        || { echo "score-broad: cross-validation failed" >&2; exit 1; }
    cat "$tmp/cv.txt"
    printf '\n%-40s %8.3f | cross-validated %s | VQF %8.3f | offline VQF %8.3f\n' "in-sample mean (defaults)" \
        "$(python3 -c "print($sum / $n)")" "$(sed -n 's/^CV_LOTO=\([^ ]*\).*/\1/p' "$tmp/cv.txt")" \
        "$(python3 -c "print($vsum / $n)")" "$(python3 -c "print($osum / $n)")"
fi
