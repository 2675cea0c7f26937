#!/usr/bin/env python3
"""campaign_noise.py BASE_RUNS NULL_RUNS [CHANGE_RUNS ...]: how far a campaign moves by
chance, and whether a change moved it further.

BASE_RUNS and NULL_RUNS are two campaigns of the same spec whose code differs
by a change that cannot matter (a null change: the fifty-third session's
d_min_m 0.0201 instead of 0.02). Each is a runs.csv (scripts/campaign_report.py)
or a campaign directory (runs/*/summary.json). A run's course is chaotic: any
change to what SLAM integrates redraws its registrations, so the null
campaign's per-run differences from the base are the noise of one run, and
their spread gives the noise of a campaign mean over the same runs:

    band = 2 * sd(null - base) / sqrt(n)      (about 95 %, runs independent)

For each CHANGE_RUNS campaign, its paired mean difference from BASE_RUNS is
printed beside the band, with "beyond" when it lies outside it, and its
median difference and how many runs went up / down (a sign test: under no
effect, up and down are equally likely; the null's counts show it). The
nbv / nearest path ratio (the campaign's pairs, issue 12) gets its band by
resampling the null's pairs (bootstrap, a fixed seed).

Only runs present in BASE_RUNS and in every other campaign are compared."""
import csv
import json
import math
import os
import random
import sys

METRICS = [  # key, label, format
    ('coverage_2d', 'coverage_2d', '{:+.4f}'),
    ('ate_rmse_m', 'ATE [m]', '{:+.4f}'),
    ('ate_online_rmse_m', 'online ATE [m]', '{:+.4f}'),
    ('map_precision_above_floor', 'precision above floor', '{:+.4f}'),
    ('path_length_m', 'path per run [m]', '{:+.1f}'),
    ('loop_closures', 'loop closures per run', '{:+.2f}'),
    ('min_clearance_m', 'min clearance [m]', '{:+.4f}'),
]


def load(src):
    """Run name -> {metric: float} from a runs.csv or a campaign directory."""
    runs = {}
    if not os.path.exists(src):
        sys.exit(f'campaign_noise.py: {src}: no such runs.csv or campaign directory')
    if os.path.isdir(src):
        if not os.path.isdir(os.path.join(src, 'runs')):
            sys.exit(f'campaign_noise.py: {src}: a campaign directory holds runs/ (scripts/campaign.sh)')
        top = os.path.join(src, 'runs')
        for name in sorted(os.listdir(top)):
            f = os.path.join(top, name, 'summary.json')
            if os.path.exists(f):
                d = json.load(open(f))
                runs[name] = d
    else:
        rows = list(csv.DictReader(open(src)))
        if rows and 'run_dir' not in rows[0]:
            sys.exit(f'campaign_noise.py: {src}: no run_dir column (a runs.csv of scripts/campaign_report.py?)')
        for r in rows:
            runs[os.path.basename(r['run_dir'].rstrip('/'))] = r
    out = {}
    for name, d in runs.items():
        try:
            out[name] = {k: float(d.get(k) or 0) for k, _, _ in METRICS}
        except (TypeError, ValueError) as e:
            sys.exit(f'campaign_noise.py: {src}: run {name}: {e}')
    return out


def sd(v):
    if len(v) < 2:
        return float('nan')
    m = sum(v) / len(v)
    return math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1))


def median(v):
    w = sorted(v)
    m = len(w) // 2
    return w[m] if len(w) % 2 else 0.5 * (w[m - 1] + w[m])


def updown(d, eps=1e-9):
    """Runs whose value went up / down (a sign test's counts)."""
    return f'{sum(x > eps for x in d)} / {sum(x < -eps for x in d)}'


def pairs_ratio(runs, names):
    """Sum of nbv paths over sum of nearest paths, over the (world, robot,
    seed) pairs that have both strategies among names."""
    key = {}
    for n in names:
        for s in ('_nbv_', '_nearest_'):
            if s in n:
                key.setdefault(n.replace(s, '_'), {})[s.strip('_')] = runs[n]['path_length_m']
    ps = [(v['nbv'], v['nearest']) for v in key.values() if 'nbv' in v and 'nearest' in v]
    return ps


def ratio(ps):
    return sum(a for a, _ in ps) / sum(b for _, b in ps) if ps else float('nan')


def main(argv):
    if len(argv) < 3 or argv[1] in ('-h', '--help'):
        print(__doc__)
        return 0 if len(argv) > 1 and argv[1] in ('-h', '--help') else 2
    srcs = argv[1:]
    camps = [load(s) for s in srcs]
    for s, c in zip(srcs, camps):
        if not c:
            sys.exit(f'campaign_noise.py: {s}: no finished runs')
    names = sorted(set.intersection(*(set(c) for c in camps)))
    n = len(names)
    if n < 2:
        sys.exit(f'campaign_noise.py: only {n} run(s) common to every campaign')
    base, null, changes = camps[0], camps[1], camps[2:]
    print(f'{n} runs common to {len(srcs)} campaigns (base {srcs[0]}, null {srcs[1]})\n')
    head = ('| metric | base mean | null - base: mean | median | up / down | sd of one run\'s difference '
            '| band of a mean (2 sd / sqrt(n)) |')
    head += ''.join(f' {os.path.basename(os.path.normpath(s))} - base: mean (median, up / down) |' for s in srcs[2:])
    print(head)
    print('|---' * (head.count('|') - 1) + '|')
    for k, label, fmt in METRICS:
        b = [base[r][k] for r in names]
        dn = [null[r][k] - base[r][k] for r in names]
        s = sd(dn)
        band = 2 * s / math.sqrt(n)
        row = (f'| {label} | {sum(b) / n:.4g} | {fmt.format(sum(dn) / n)} | {fmt.format(median(dn))} | '
               f'{updown(dn)} | {s:.4g} | +-{band:.3g} |')
        for c in changes:
            d = [c[r][k] - base[r][k] for r in names]
            dc = sum(d) / n
            row += f' {fmt.format(dc)}{" (beyond)" if abs(dc) > band else ""} ({fmt.format(median(d))}, {updown(d)}) |'
        print(row)
    # the nbv / nearest ratio: bootstrap over the pairs of the null change
    pb, pn = pairs_ratio(base, names), pairs_ratio(null, names)
    if pb and len(pb) == len(pn):
        rng = random.Random(1)
        idx = list(range(len(pb)))
        deltas = []
        for _ in range(2000):
            pick = [rng.choice(idx) for _ in idx]
            deltas.append(ratio([pn[i] for i in pick]) - ratio([pb[i] for i in pick]))
        deltas.sort()
        lo, hi = deltas[int(0.025 * len(deltas))], deltas[int(0.975 * len(deltas)) - 1]
        half = max(abs(lo), abs(hi))
        row = (f'| nbv / nearest path ({len(pb)} pairs) | {ratio(pb):.3f} | {ratio(pn) - ratio(pb):+.3f} | | | | '
               f'+-{half:.3f} (bootstrap of the null\'s pairs) |')
        for c in changes:
            d = ratio(pairs_ratio(c, names)) - ratio(pb)
            row += f' {d:+.3f}{" (beyond)" if abs(d) > half else ""} |'
        print(row)
    print('\nPer run, null - base (the noise of one run):\n')
    print('| run | coverage | ATE [m] | path [m] |')
    print('|---|---|---|---|')
    for r in names:
        print(f"| {r} | {null[r]['coverage_2d'] - base[r]['coverage_2d']:+.4f} | "
              f"{null[r]['ate_rmse_m'] - base[r]['ate_rmse_m']:+.4f} | "
              f"{null[r]['path_length_m'] - base[r]['path_length_m']:+.1f} |")
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
