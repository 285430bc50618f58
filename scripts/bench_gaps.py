#!/usr/bin/env python3
"""Orientation through dropouts: how fast `armadillo fuse` finds its way back after a gap, next to
VQF on the same samples in the same run (issue 12's benchmark; docs/BENCHMARKS.md).

    bench_gaps.py [--armadillo BIN] [--data DIR] [--gaps 0.3,1,3] [--at 40,80,120] [--start 30]

For every BROAD trial in DIR and every gap length L, the samples with t in [T, T + L) are cut out
at each T of --at (the t column keeps the gap, as a host that stamps arrivals sees it). Both
filters run on the cut file; the error (BROAD's total angle, scalar |q_est q_truth^-1|) is taken
at the samples 0-1 s, 1-3 s and 3-10 s after each gap's end, and each window's median is printed.
A second run starts every trial at t = --start (mid-movement, no rest phase) and prints the same
windows after the start. The no-gap RMSE over the movement phase (score_broad.py's metric) is
printed too, so one run shows that the gap handling costs nothing without gaps.

VQF (pip install vqf) gets the cut samples with its nominal sample time: it does not know a gap
happened, exactly as in the issue's comparison. Prints numbers; never passes or fails on them.
"""
import argparse
import gzip
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

EUS_TO_ENU = np.array([np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0])   # +90 deg about x
WINDOWS = ((0.0, 1.0), (1.0, 3.0), (3.0, 10.0))


def qmul(a, b):
    a, b = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float))
    w1, x1, y1, z1 = np.moveaxis(a, -1, 0)
    w2, x2, y2, z2 = np.moveaxis(b, -1, 0)
    return np.stack([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2], axis=-1)


def error_deg(q_est_enu, q_truth):
    """BROAD's total error angle in degrees; NaN where the truth is missing, 180 where the estimate is."""
    conj = q_truth * np.array([1.0, -1.0, -1.0, -1.0])
    d = qmul(q_est_enu / np.linalg.norm(q_est_enu, axis=1, keepdims=True), conj)
    err = np.degrees(2.0 * np.arccos(np.clip(np.abs(d[:, 0]), 0.0, 1.0)))
    err[~np.all(np.isfinite(q_est_enu), axis=1)] = 180.0
    err[~np.all(np.isfinite(q_truth), axis=1)] = np.nan
    return err


def load(path):
    with gzip.open(path, 'rt') as f:
        header = f.readline().strip().split(',')
    return header, np.loadtxt(path, delimiter=',', skiprows=1, ndmin=2)


def run_armadillo(binary, imu_header, imu, tmp, name):
    src, dst = Path(tmp) / f'{name}.imu.csv', Path(tmp) / f'{name}.q.csv'
    np.savetxt(src, imu, delimiter=',', header=','.join(imu_header), comments='', fmt='%.9g')
    r = subprocess.run([binary, 'fuse', '--in', str(src), '--out', str(dst)], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f'bench_gaps: armadillo fuse failed on {name}: {r.stderr.strip()}')
    q = np.loadtxt(dst, delimiter=',', skiprows=1, ndmin=2)[:, 1:5]
    return qmul(EUS_TO_ENU, q)


def run_vqf(imu, ts):
    from vqf import VQF
    v = VQF(ts)
    out = v.updateBatch(np.ascontiguousarray(imu[:, 1:4]), np.ascontiguousarray(imu[:, 4:7]),
                        np.ascontiguousarray(imu[:, 7:10]))
    return out['quat9D']


def window_medians(t, err, t0):
    meds = []
    for a, b in WINDOWS:
        sel = (t >= t0 + a) & (t < t0 + b) & np.isfinite(err)
        meds.append(float(np.median(err[sel])) if sel.any() else float('nan'))
    return meds


def main():
    here = Path(__file__).resolve().parent.parent
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--armadillo', default=str(here / 'build' / 'bin' / 'armadillo'))
    ap.add_argument('--data', default=str(here.parent / 'shared' / 'data' / 'broad-dev'))
    ap.add_argument('--gaps', default='0.3,1,3')
    ap.add_argument('--at', default='40,80,120')
    ap.add_argument('--start', type=float, default=30.0)
    ap.add_argument('--no-vqf', action='store_true', help='skip the VQF comparison (faster tuning runs)')
    args = ap.parse_args()
    gaps = [float(x) for x in args.gaps.split(',')]
    at = [float(x) for x in args.at.split(',')]
    try:
        import vqf  # noqa: F401
        have_vqf = not args.no_vqf
    except ImportError:
        have_vqf = False
        print('vqf not installed (pip install vqf): no comparison')
    trials = sorted(Path(args.data).glob('*_imu.csv.gz'))
    if not trials:
        sys.exit(f'bench_gaps: no *_imu.csv.gz in {args.data}')

    rows, starts, nogap = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for imu_path in trials:
            trial = imu_path.name[:-len('_imu.csv.gz')]
            header, imu = load(imu_path)
            _, truth = load(imu_path.with_name(trial + '_truth.csv.gz'))
            mh, mov = load(imu_path.with_name(trial + '_movement.csv.gz'))
            movement = mov[:, mh.index('movement')] > 0.5
            t, q_truth = imu[:, 0], truth[:, 1:5]
            ts = float(np.median(np.diff(t)))

            err = error_deg(run_armadillo(args.armadillo, header, imu, tmp, trial), q_truth)
            ok = movement & np.isfinite(err)
            nogap.append((trial, float(np.sqrt(np.mean(err[ok] ** 2)))))

            for length in gaps:
                keep = np.ones(len(t), bool)
                for g in at:
                    keep &= ~((t >= g) & (t < g + length))
                cut_imu, cut_truth, cut_t = imu[keep], q_truth[keep], t[keep]
                ours = error_deg(run_armadillo(args.armadillo, header, cut_imu, tmp, f'{trial}-gap{length}'), cut_truth)
                theirs = error_deg(run_vqf(cut_imu, ts), cut_truth) if have_vqf else np.full(len(cut_t), np.nan)
                for g in at:
                    rows.append((trial, length, g, window_medians(cut_t, ours, g + length),
                                 window_medians(cut_t, theirs, g + length)))

            late = t >= args.start
            ours = error_deg(run_armadillo(args.armadillo, header, imu[late], tmp, f'{trial}-start'), q_truth[late])
            theirs = error_deg(run_vqf(imu[late], ts), q_truth[late]) if have_vqf else np.full(late.sum(), np.nan)
            starts.append((trial, window_medians(t[late], ours, t[late][0]), window_medians(t[late], theirs, t[late][0])))

    def fmt(v):
        return ' '.join(f'{x:6.2f}' for x in v)

    names = '  '.join(f'{int(a)}-{int(b)}s' for a, b in WINDOWS)
    print(f'median error (deg) after each gap; windows {names}')
    print(f'{"trial":36s} {"gap s":>5s} {"at s":>5s} | {"ARMadillo":^20s} | {"VQF":^20s}')
    for trial, length, g, o, v in rows:
        print(f'{trial:36s} {length:5.1f} {g:5.0f} | {fmt(o)} | {fmt(v)}')
    for length in gaps:
        o = np.nanmean([r[3] for r in rows if r[1] == length], axis=0)
        v = np.nanmean([r[4] for r in rows if r[1] == length], axis=0)
        print(f'{"mean over trials and gap times":36s} {length:5.1f} {"":5s} | {fmt(o)} | {fmt(v)}')
    o_all = np.nanmean([r[3] for r in rows], axis=0)
    v_all = np.nanmean([r[4] for r in rows], axis=0)
    print(f'{"MEAN over every gap":36s} {"all":>5s} {"":5s} | {fmt(o_all)} | {fmt(v_all)}')
    print(f'\nstart mid-movement at t = {args.start:g} s: median error (deg), windows {names}')
    for trial, o, v in starts:
        print(f'{trial:36s} | {fmt(o)} | {fmt(v)}')
    o_s = np.nanmean([s[1] for s in starts], axis=0)
    v_s = np.nanmean([s[2] for s in starts], axis=0)
    print(f'{"MEAN":36s} | {fmt(o_s)} | {fmt(v_s)}')
    print('\nwithout gaps: total RMSE over the movement phase (deg)')
    for trial, e in nogap:
        print(f'{trial:36s} {e:6.3f}')
    print(f'{"MEAN":36s} {np.mean([e for _, e in nogap]):6.3f}')
    print(f'GAPS_1_3S={o_all[1]:.3f} GAPS_3_10S={o_all[2]:.3f} START_1_3S={o_s[1]:.3f} '
          f'NOGAP_MEAN={np.mean([e for _, e in nogap]):.3f} VQF_GAPS_1_3S={v_all[1]:.3f} VQF_GAPS_3_10S={v_all[2]:.3f}')


if __name__ == '__main__':
    main()
