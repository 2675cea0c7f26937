#!/usr/bin/env python3
# collect.py BASE_RUNS_DIR TAG [TAG...]: per run base ATE (online run) vs replay ATE per variant
import json, os, sys, glob, statistics as st
base=sys.argv[1]; tags=sys.argv[2:]
rows=[]
for tdir in sorted(glob.glob(f'out/rp/{tags[0]}/*/summary.json')):
    n=tdir.split('/')[-2]
    b=json.load(open(f'{base}/{n}/summary.json'))
    r=[n, b['ate_rmse_m'], b.get('ate_online_rmse_m'), b.get('loop_closures')]
    ok=True
    for t in tags:
        f=f'out/rp/{t}/{n}/summary.json'
        if not os.path.exists(f): ok=False; break
        d=json.load(open(f)); r += [d['ate_rmse_m'], d.get('ate_online_rmse_m'), d.get('loop_closures')]
    if ok: rows.append(r)
hdr='| run | base ATE / online / closures |' + ''.join(f' {t} ATE / online / closures |' for t in tags)
print(hdr); print('|---'*(1+len(tags)+1)+'|')
for r in rows:
    print(f'| {r[0]} |' + ''.join(f' {r[i]:.4f} / {r[i+1]:.4f} / {r[i+2]} |' for i in range(1,len(r),3)))
print(f'\n{len(rows)} runs')
for i,t in enumerate(['base']+tags):
    a=[r[1+3*i] for r in rows]; o=[r[2+3*i] for r in rows]
    print(f'{t}: ATE mean {st.mean(a):.4f} worst {max(a):.4f}; online mean {st.mean(o):.4f}; closures {sum(r[3+3*i] or 0 for r in rows)}')
    if i: 
        better=sum(1 for r in rows if r[1+3*i] < r[1]-0.002); worse=sum(1 for r in rows if r[1+3*i] > r[1]+0.002)
        print(f'   vs base: {better} better, {worse} worse (2 mm), {len(rows)-better-worse} same')
