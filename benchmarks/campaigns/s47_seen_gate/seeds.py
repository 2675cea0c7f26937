#!/usr/bin/python3
"""Two seeds of the same campaign (runs.csv of scripts/campaign_report.py):
per building the path of each strategy under both seeds, the nbv / nearest
ratio per seed, and how far one seed's path lies from the other's (the
spread a change must beat to show on a campaign of that size).

    seeds.py SEED1/runs.csv SEED2/runs.csv [ROBOT]
"""
import csv, math, os, statistics, sys

def load(p, robot):
    out = {}
    for r in csv.DictReader(open(p)):
        if r['exit_status'] == '0' and r['robot'] == robot:
            out[(os.path.basename(os.path.dirname(r['world'])), r['strategy'])] = r
    return out

robot = sys.argv[3] if len(sys.argv) > 3 else 'compact'
a, b = load(sys.argv[1], robot), load(sys.argv[2], robot)
blds = sorted({k[0] for k in a} & {k[0] for k in b}, key=lambda s: int(s[1:]))
path = lambda d, bl, s: float(d[(bl, s)]['path_length_m'])
cov = lambda d, bl, s: float(d[(bl, s)]['coverage_2d'])
print('| building | nbv s1 [m] | nbv s2 [m] | nearest s1 [m] | nearest s2 [m] | nbv/nearest s1 | s2 | coverage nbv s1 / s2 |')
print('|---|---|---|---|---|---|---|---|')
ratios = {1: [], 2: []}
logs = {'nbv': [], 'nearest': []}
for bl in blds:
    if not all((bl, s) in d for d in (a, b) for s in ('nbv', 'nearest')):
        continue
    r1 = path(a, bl, 'nbv') / path(a, bl, 'nearest')
    r2 = path(b, bl, 'nbv') / path(b, bl, 'nearest')
    ratios[1].append(r1); ratios[2].append(r2)
    for s in logs:
        logs[s].append(math.log(path(b, bl, s) / path(a, bl, s)))
    print(f"| {bl} | {path(a, bl, 'nbv'):.1f} | {path(b, bl, 'nbv'):.1f} | {path(a, bl, 'nearest'):.1f} | "
          f"{path(b, bl, 'nearest'):.1f} | {r1:.3f} | {r2:.3f} | {cov(a, bl, 'nbv'):.4f} / {cov(b, bl, 'nbv'):.4f} |")
n = len(ratios[1])
both = ratios[1] + ratios[2]
print()
print(f"nbv / nearest, mean over {n} buildings: seed 1 {statistics.mean(ratios[1]):.3f}, seed 2 "
      f"{statistics.mean(ratios[2]):.3f}; both seeds ({2 * n} pairs) {statistics.mean(both):.3f} "
      f"(worst {max(both):.3f}, {sum(x > 1 for x in both)} above 1.0x)")
for s, v in logs.items():
    sd = statistics.stdev(v)
    print(f"{s}: seed 2 / seed 1 path per building {', '.join(f'{math.exp(x):.2f}' for x in v)}; "
          f"sd of the log ratio {sd:.3f}: a paired before / after over {n} buildings moves its "
          f"mean path by about {100 * sd / math.sqrt(n):.1f} % (one standard error) from the course alone")
