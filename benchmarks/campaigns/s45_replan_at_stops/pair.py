#!/usr/bin/python3
"""Pairs two campaigns (runs.csv of scripts/campaign_report.py) per building:
nbv and nearest before and after, the nbv / nearest path ratio of each
combination, and the summary rows (coverage mean / worst, path, ATE, collisions,
minimum clearance, simulated time, ends).

    pair.py BEFORE/runs.csv AFTER/runs.csv [ROBOT]
"""
import csv, os, statistics, sys

def load(p):
    out = {}
    for r in csv.DictReader(open(p)):
        if r['exit_status'] != '0':
            continue
        b = os.path.basename(os.path.dirname(r['world']))
        out[(b, r['robot'], r['strategy'])] = r
    return out

before, after = load(sys.argv[1]), load(sys.argv[2])
robot = sys.argv[3] if len(sys.argv) > 3 else 'compact'
f = lambda r, k: float(r[k])
blds = sorted({k[0] for k in before if k[1] == robot} & {k[0] for k in after if k[1] == robot},
              key=lambda b: int(b[1:]) if b[1:].isdigit() else 0)
print('| building | nbv before [m] | nbv after [m] | nearest before [m] | nearest after [m] | nbv/nearest before | after/nearest before | after/nearest after | coverage nbv before -> after |')
print('|---|---|---|---|---|---|---|---|---|')
rat = {'b': [], 'ab': [], 'aa': []}
for b in blds:
    k = lambda s: (b, robot, s)
    if not all(x in d for x in (k('nbv'), k('nearest')) for d in (before, after)):
        continue
    nb, na = f(before[k('nbv')], 'path_length_m'), f(after[k('nbv')], 'path_length_m')
    rb, ra = f(before[k('nearest')], 'path_length_m'), f(after[k('nearest')], 'path_length_m')
    rat['b'].append(nb / rb); rat['ab'].append(na / rb); rat['aa'].append(na / ra)
    print(f"| {b} | {nb:.1f} | {na:.1f} | {rb:.1f} | {ra:.1f} | {nb/rb:.3f} | {na/rb:.3f} | {na/ra:.3f} | "
          f"{f(before[k('nbv')],'coverage_2d'):.4f} -> {f(after[k('nbv')],'coverage_2d'):.4f} |")
n = len(rat['b'])
if n:
    print(f"| mean ({n}) | | | | | {statistics.mean(rat['b']):.3f} | {statistics.mean(rat['ab']):.3f} | {statistics.mean(rat['aa']):.3f} | |")
    print(f"| above 1.0x | | | | | {sum(x > 1 for x in rat['b'])} | {sum(x > 1 for x in rat['ab'])} | {sum(x > 1 for x in rat['aa'])} | |")
print()
print('| runs | n | coverage mean / worst | path [m] | path per m^2 mean / worst | ATE mean / worst [m] | collisions | min clearance [m] | sim time [s] | ends by itself |')
print('|---|---|---|---|---|---|---|---|---|---|')
for label, d in (('before', before), ('after', after)):
    for s in ('nbv', 'nearest'):
        rs = [d[(b, robot, s)] for b in blds if (b, robot, s) in d]
        if not rs:
            continue
        cov = [f(r, 'coverage_2d') for r in rs]
        ate = [f(r, 'ate_rmse_m') for r in rs]
        ppm = [f(r, 'path_per_m2') for r in rs if r.get('path_per_m2')]
        ends = sum(r['termination_reason'] not in ('max_steps', 'max_sim_time') for r in rs)
        ppm_s = f"{statistics.mean(ppm):.3f} / {max(ppm):.3f}" if ppm else '-'
        print(f"| {robot} {s} {label} | {len(rs)} | {statistics.mean(cov):.4f} / {min(cov):.3f} | {sum(f(r,'path_length_m') for r in rs):.0f} | {ppm_s} | "
              f"{statistics.mean(ate):.3f} / {max(ate):.3f} | {sum(int(float(r['collisions'])) for r in rs)} | "
              f"{min(f(r,'min_clearance_m') for r in rs):.3f} | {sum(f(r,'sim_time_s') for r in rs):.0f} | {ends} / {len(rs)} |")
