#!/usr/bin/env python3
"""pair.py BASE_RUNS_CSV RUNS_DIR: each finished run of RUNS_DIR beside the
same run of the base campaign's runs.csv (coverage, ATE, online ATE, map
precision above the floor, path, closures, collisions, min clearance), and
the means over the runs both have."""
import csv
import json
import os
import sys

base = {os.path.basename(r['run_dir']): r for r in csv.DictReader(open(sys.argv[1]))}
keys = [('coverage_2d', 'cov'), ('ate_rmse_m', 'ate'), ('ate_online_rmse_m', 'ate_onl'),
        ('map_precision_above_floor', 'prec'), ('path_length_m', 'path'),
        ('loop_closures', 'lc'), ('collisions', 'coll'), ('min_clearance_m', 'clr')]
print('| run | ' + ' | '.join(k[1] + ' base -> new' for k in keys) + ' | end |')
print('|---' * (len(keys) + 2) + '|')
sums = {k: [0.0, 0.0] for k, _ in keys}
worst = {k: [None, None] for k, _ in keys}
n = 0
for name in sorted(os.listdir(os.path.join(sys.argv[2], 'runs'))):
    f = os.path.join(sys.argv[2], 'runs', name, 'summary.json')
    if not os.path.exists(f) or name not in base:
        continue
    d = json.load(open(f))
    b = base[name]
    cells = []
    for k, _ in keys:
        bv, nv = float(b[k] or 0), float(d.get(k, 0) or 0)
        sums[k][0] += bv
        sums[k][1] += nv
        better_low = k in ('coverage_2d', 'map_precision_above_floor', 'min_clearance_m')
        for i, v in enumerate((bv, nv)):
            w = worst[k][i]
            worst[k][i] = v if w is None else (min(w, v) if better_low else max(w, v))
        cells.append(f'{bv:.4g} -> {nv:.4g}')
    n += 1
    print(f'| {name} | ' + ' | '.join(cells) + f" | {d['termination_reason']} |")
if n:
    print(f"| **mean of {n}** | " + ' | '.join(f'{s[0] / n:.4g} -> {s[1] / n:.4g}' for s in sums.values()) + ' | |')
    print(f"| **worst** | " + ' | '.join(f'{w[0]:.4g} -> {w[1]:.4g}' for w in worst.values()) + ' | |')
