import json, os, re, subprocess, sys, glob
base='/work/main/out/c_base/runs'; new='/work/main/out/rp1'
rows=[]
def loops(d):
    out=subprocess.run(['python3','/work/main/scripts/check_loops.py',d],capture_output=True,text=True).stdout
    m=re.search(r'(\d+) closure\(s\), (\d+) suspect',out)
    return (int(m.group(1)),int(m.group(2))) if m else (0,0)
for d in sorted(glob.glob(new+'/*/')):
    r=os.path.basename(d.rstrip('/'))
    if not os.path.exists(d+'summary.json'): continue
    a=json.load(open(f'{base}/{r}/summary.json'))['ate_rmse_m']
    b=json.load(open(d+'summary.json')).get('ate_rmse_m')
    ident=open(f'{base}/{r}/stops.csv').read().split('\n')[1:]==open(d+'stops.csv').read().split('\n')[1:]
    same = subprocess.run("cmp -s <(cut -d, -f1-11 %s/%s/stops.csv) <(cut -d, -f1-11 %sstops.csv)"%(base,r,d),shell=True,executable='/bin/bash').returncode==0
    la=loops(f'{base}/{r}'); lb=loops(d)
    rows.append((r,a,b,same,la,lb))
    print(f"| {r} | {a:.4f} | {b:.4f} | {'identical poses' if same else ''} | {la[0]} / {la[1]} | {lb[0]} / {lb[1]} |")
n=len(rows)
if n:
    print(f"runs {n}; mean ATE {sum(r[1] for r in rows)/n:.4f} -> {sum(r[2] for r in rows)/n:.4f}; worst {max(r[1] for r in rows):.4f} -> {max(r[2] for r in rows):.4f}; better {sum(1 for r in rows if r[2]<r[1]-1e-4)} worse {sum(1 for r in rows if r[2]>r[1]+1e-4)}; closures {sum(r[4][0] for r in rows)} -> {sum(r[5][0] for r in rows)}; suspect {sum(r[4][1] for r in rows)} -> {sum(r[5][1] for r in rows)}")
