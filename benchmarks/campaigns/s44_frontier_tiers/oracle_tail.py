#!/usr/bin/python3
"""Path at which each run first came within EPS of its final coverage (an oracle tail cut), paired nbv/nearest."""
import csv, sys, glob, os
root = sys.argv[1]; eps = float(sys.argv[2]) if len(sys.argv) > 2 else 0.002
ref = sys.argv[3] if len(sys.argv) > 3 else None  # take nearest runs from here
def cut(run):
    rows = list(csv.DictReader(open(os.path.join(run, 'coverage.csv'))))
    final = float(rows[-1]['coverage_2d'])
    for r in rows:
        if float(r['coverage_2d']) >= final - eps:
            return float(r['path_length_m']), float(rows[-1]['path_length_m']), final
res = {}
for d in [root] + ([ref] if ref else []):
    for run in glob.glob(os.path.join(d, 'runs', '*')):
        n = os.path.basename(run).split('_')
        if not os.path.exists(os.path.join(run, 'summary.json')): continue
        res.setdefault((n[0], n[1], n[2]), cut(run)) if d == root or n[2] == 'nearest' else None
rs, rf = [], []
for (w, rob, st), v in sorted(res.items()):
    if st != 'nbv': continue
    nn = res.get((w, rob, 'nearest'))
    if not nn: continue
    rs.append(v[0] / nn[0]); rf.append(v[1] / nn[1])
    print(f"{w:4} {rob:8} nbv cut {v[0]:6.1f} full {v[1]:6.1f} cov {v[2]:.3f} | nearest cut {nn[0]:6.1f} full {nn[1]:6.1f} cov {nn[2]:.3f} | ratio cut {rs[-1]:.2f} full {rf[-1]:.2f}")
if rs: print(f"mean ratio cut {sum(rs)/len(rs):.3f} full {sum(rf)/len(rf):.3f} over {len(rs)}")
