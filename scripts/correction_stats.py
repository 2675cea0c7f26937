#!/usr/bin/env python3
"""Accepted registrations of campaign runs against the ground truth: how far
each moved the pose from the odometry prediction, in odometry stds, and
whether it moved it toward the truth.

    scripts/correction_stats.py RUN_DIR [RUN_DIR ...]

Each RUN_DIR is a campaign run (scripts/campaign.sh): its run.json names the
world, whose building.json (written by voxplore-worldgen) gives the start
pose; stops.csv, trajectory_gt.tum and params.ini come from voxplore-explore.
Runs of worlds without a building.json are skipped (named on stderr).

The std of a stop's prediction is summed over the odometry increments since
the last accepted registration, with the run's own [icp]
odometry_std_xy_per_m, odometry_std_xy_per_rad and odometry_std_xy_min_m
(SlamIcp's gate uses the same sum). Prints the accepted registrations per
band of the correction in stds (how many made the position error more than
5 cm worse), then every correction above --min-m and --min-stds with its
goodness, information ratio and the error before and after.
"""
import argparse
import configparser
import csv
import json
import math
import os
import sys


def read_tum(path):
    with open(path) as f:
        return [list(map(float, l.split())) for l in f if l.strip() and not l.startswith('#')]


def odometry_stds(params_path):
    cp = configparser.ConfigParser(inline_comment_prefixes=('//', '#'), strict=False)
    with open(params_path) as f:
        cp.read_file(f)
    get = lambda k, d: float(cp.get('icp', k, fallback=str(d)))
    return get('odometry_std_xy_per_m', 0.01), get('odometry_std_xy_per_rad', 0.0573), \
        get('odometry_std_xy_min_m', 0.005)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('runs', nargs='+', help='campaign run directories')
    ap.add_argument('--min-m', type=float, default=0.10, help='list corrections above this [m] (0.10)')
    ap.add_argument('--min-stds', type=float, default=8.0, help='... and this many stds (8)')
    a = ap.parse_args()
    bands = [(0, 4), (4, 8), (8, 12), (12, math.inf)]
    tally = {b: [0, 0] for b in bands}
    listed = []
    for run in a.runs:
        try:
            with open(os.path.join(run, 'run.json')) as f:
                world = json.load(f)['world']
            bj = os.path.join(os.path.dirname(world), 'building.json')
            if not os.path.exists(bj):
                sys.stderr.write(f'{run}: no building.json beside {world}: skipped\n')
                continue
            with open(bj) as f:
                start = json.load(f)['start']
            per_m, per_rad, min_m = odometry_stds(os.path.join(run, 'params.ini'))
            gt = read_tum(os.path.join(run, 'trajectory_gt.tum'))
            with open(os.path.join(run, 'stops.csv')) as f:
                rows = list(csv.DictReader(f))
        except (OSError, KeyError, ValueError) as e:
            sys.stderr.write(f'{run}: {e}: skipped\n')
            continue
        if len(gt) != len(rows):
            sys.stderr.write(f'{run}: {len(rows)} stops but {len(gt)} ground-truth poses: skipped\n')
            continue
        std, prev = 0.0, None
        for r, g in zip(rows, gt):
            odo = (float(r['odo_x']), float(r['odo_y']), math.radians(float(r['odo_yaw_deg'])))
            if prev is not None:
                d = math.hypot(odo[0] - prev[0], odo[1] - prev[1])
                turn = abs(math.atan2(math.sin(odo[2] - prev[2]), math.cos(odo[2] - prev[2])))
                std += max(min_m, per_m * d + per_rad * turn)
            prev = odo
            if r['icp_accepted'] != '1':
                continue
            px, py, x, y = (float(r[k]) for k in ('pred_x', 'pred_y', 'x', 'y'))
            # The map frame is the world's shifted to the start pose (planar, yaw 0 at the start).
            gx, gy = g[1] - start[0], g[2] - start[1]
            corr = math.hypot(x - px, y - py)
            k = corr / max(std, 1e-9)
            before, after = math.hypot(px - gx, py - gy), math.hypot(x - gx, y - gy)
            for b in bands:
                if b[0] <= k < b[1]:
                    tally[b][0] += 1
                    tally[b][1] += after - before > 0.05
            if corr > a.min_m and k > a.min_stds:
                listed.append((os.path.basename(os.path.normpath(run)), r['stop'], corr, std, k,
                               r['icp_goodness'], r['icp_info_ratio'], before, after))
            std = 0.0
    for b, (n, worse) in tally.items():
        print(f'correction {b[0]}-{b[1]} stds: {n} accepted, {worse} made the position error > 5 cm worse')
    print(f'corrections above {a.min_m} m and {a.min_stds} stds:')
    print('run stop correction_m std_m stds goodness info_ratio error_before_m error_after_m')
    for t in listed:
        print(f'{t[0]} {t[1]} {t[2]:.3f} {t[3]:.4f} {t[4]:.1f} {t[5]} {t[6]} {t[7]:.3f} {t[8]:.3f}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
