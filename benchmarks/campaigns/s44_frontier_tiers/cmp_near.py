#!/usr/bin/python3
"""nearest runs of an experiment dir against a reference's nearest and nbv runs."""
import json, sys, glob, os
exp, ref, nbvdir = sys.argv[1], sys.argv[2], sys.argv[3]
def s(p):
    p = os.path.join(p, 'summary.json')
    return json.load(open(p)) if os.path.exists(p) else None
r1=[];r2=[]
for run in sorted(glob.glob(os.path.join(exp, 'runs', '*'))):
    n = os.path.basename(run); e = s(run); b = s(os.path.join(ref, 'runs', n)); v = s(os.path.join(nbvdir, 'runs', n.replace('_nearest_', '_nbv_')))
    if not (e and b and v): continue
    r1.append(v['path_length_m']/b['path_length_m']); r2.append(v['path_length_m']/e['path_length_m'])
    print(f"{n:24} nearest tiers off {e['path_length_m']:6.1f} {e['coverage_2d']:.3f} | thesis {b['path_length_m']:6.1f} {b['coverage_2d']:.3f} | nbv off {v['path_length_m']:6.1f} | ratio vs thesis nearest {r1[-1]:.2f}, vs tierless nearest {r2[-1]:.2f}")
if r1: print(f"n={len(r1)} mean ratio nbv(off)/nearest(thesis) {sum(r1)/len(r1):.3f}, nbv(off)/nearest(off) {sum(r2)/len(r2):.3f}")
