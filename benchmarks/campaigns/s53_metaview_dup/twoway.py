#!/usr/bin/env python3
"""twoway.py BASE_RUNS BASE_REPLAYS AFTER_RUNS AFTER_REPLAYS: a SLAM change
measured on the same observations both ways. Forward: each base run (change
off, online) against its rawlog replayed with the change on. Reverse: each
after run (change on, online) against its rawlog replayed with it off.
Every finished run counts, none is picked. A run's ATE is set by a few
failed registrations that any change of the SLAM redraws, so one way alone
can show a gain the other way does not (fifty-third session: forward -21 %,
reverse +6 %)."""
import json
import os
import sys


def ate(d):
    f = os.path.join(d, 'summary.json')
    return json.load(open(f))['ate_rmse_m'] if os.path.exists(f) else None


def pairs(runs, replays):
    out = []
    for n in sorted(os.listdir(replays)):
        a, b = ate(os.path.join(runs, n)), ate(os.path.join(replays, n))
        if a is not None and b is not None:
            out.append((n, a, b))
    return out


fwd = [(n, off, on) for n, off, on in pairs(sys.argv[1], sys.argv[2])]
rev = [(n, off, on) for n, on, off in pairs(sys.argv[3], sys.argv[4])]
print('| set | runs | ATE mean off -> on [m] | worst off -> on | on better / worse by > 2 mm |')
print('|---|---|---|---|---|')
for name, ps in (('forward (base rawlogs)', fwd), ('reverse (after rawlogs)', rev), ('both', fwd + rev)):
    if not ps:
        continue
    n = len(ps)
    off = sum(p[1] for p in ps) / n
    on = sum(p[2] for p in ps) / n
    better = sum(p[2] < p[1] - 0.002 for p in ps)
    worse = sum(p[2] > p[1] + 0.002 for p in ps)
    print(f'| {name} | {n} | {off:.4f} -> {on:.4f} | {max(p[1] for p in ps):.3f} -> {max(p[2] for p in ps):.3f} | {better} / {worse} |')
print()
print('| run | set | off | on |')
print('|---|---|---|---|')
for tag, ps in (('forward', fwd), ('reverse', rev)):
    for n, off, on in ps:
        print(f'| {n} | {tag} | {off:.4f} | {on:.4f} |')
