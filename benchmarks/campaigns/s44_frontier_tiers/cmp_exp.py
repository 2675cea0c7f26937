#!/usr/bin/python3
"""Compare nbv runs of an experiment campaign dir against a reference campaign's nbv and nearest runs."""
import json, sys, glob, os
exp, ref = sys.argv[1], sys.argv[2]
def summ(run):
    p = os.path.join(run, 'summary.json')
    if not os.path.exists(p): return None
    d = json.load(open(p))
    return d['path_length_m'], d['coverage_2d'], d.get('termination_reason', '')[:22], d.get('collisions'), d.get('min_clearance_m')
tot = [0, 0, 0]; ratios = []; rr = []
for run in sorted(glob.glob(os.path.join(exp, 'runs', '*')), key=lambda s: int(os.path.basename(s).split('_')[0][1:])):
    name = os.path.basename(run)
    e = summ(run)
    if not e: continue
    b = summ(os.path.join(ref, 'runs', name))
    n = summ(os.path.join(ref, 'runs', name.replace('_nbv_', '_nearest_')))
    if not b or not n: continue
    ratios.append(e[0] / n[0]); rr.append(b[0] / n[0])
    tot[0] += e[0]; tot[1] += b[0]; tot[2] += n[0]
    print(f"{name:22} exp {e[0]:6.1f} {e[1]:.3f} {e[2]:22} col {e[3]} clr {e[4]:.3f} | ref {b[0]:6.1f} {b[1]:.3f} | nearest {n[0]:6.1f} {n[1]:.3f} | ratio {ratios[-1]:.2f} (ref {rr[-1]:.2f})")
if ratios: print(f"n={len(ratios)} path exp {tot[0]:.0f} ref {tot[1]:.0f} nearest {tot[2]:.0f}; mean ratio exp {sum(ratios)/len(ratios):.3f} ref {sum(rr)/len(rr):.3f}")
