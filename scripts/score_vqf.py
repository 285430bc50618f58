#!/usr/bin/env python3
"""VQF (real time) and offline VQF on the BROAD trials, scored with the same metric as
`armadillo fuse` in scripts/score-broad.sh (which runs this in the same run and prints both
beside ARMadillo's figures).

    score_vqf.py DATA_DIR SCORER

For every <trial>_imu.csv.gz in DATA_DIR: VQF (pip install vqf; Laidig & Seel 2023) with its
default parameters and the median sample time, 9-axis output (`quat9D`, sensor → ENU), once
through `VQF.updateBatch` (causal) and once through `offlineVQF` (looks ahead: forward and backward
bias estimation). Scored by SCORER's score_files (BROAD's metric, movement phase, no alignment).
Prints one line per trial: `trial vqf_total vqf_heading vqf_incl off_total off_heading off_incl`.
"""
import importlib.util
import sys
import tempfile
from pathlib import Path

import numpy as np


def main():
    if len(sys.argv) != 3:
        sys.exit('usage: score_vqf.py DATA_DIR SCORER')
    data, scorer_path = Path(sys.argv[1]), Path(sys.argv[2])
    spec = importlib.util.spec_from_file_location('score_broad', scorer_path)
    scorer = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(scorer)
    from vqf import VQF, offlineVQF

    trials = sorted(data.glob('*_imu.csv.gz'))
    if not trials:
        sys.exit(f'score_vqf: no *_imu.csv.gz in {data}')
    with tempfile.TemporaryDirectory() as tmp:
        for imu_path in trials:
            trial = imu_path.name[:-len('_imu.csv.gz')]
            _, imu = scorer.load_csv(imu_path)
            t = imu[:, 0]
            gyr, acc, mag = (np.ascontiguousarray(imu[:, i:i + 3]) for i in (1, 4, 7))
            ts = float(np.median(np.diff(t)))
            rt = VQF(ts).updateBatch(gyr, acc, mag)['quat9D']
            off = offlineVQF(gyr, acc, mag, ts, {})['quat9D']
            cols = []
            for name, q in (('vqf', rt), ('offline', off)):
                est = Path(tmp) / f'{trial}.{name}.csv'
                np.savetxt(est, np.column_stack([t, q]), delimiter=',', header='t,qw,qx,qy,qz',
                           comments='', fmt='%.9g')
                r = scorer.score_files(str(est), str(imu_path.with_name(trial + '_truth.csv.gz')), None,
                                       use_movement=True, est_frame='ENU')
                cols += [r['total_rmse_deg'], r['heading_rmse_deg'], r['inclination_rmse_deg']]
            print(trial, ' '.join(f'{c:.3f}' for c in cols))


if __name__ == '__main__':
    main()
