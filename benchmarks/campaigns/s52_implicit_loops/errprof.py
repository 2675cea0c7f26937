#!/usr/bin/env python3
# errprof.py A_DIR B_DIR [bin]: final and online position error per stop range (start-aligned)
import sys, math
def tum(p):
    d={}
    for l in open(p):
        if l.startswith('#') or not l.strip(): continue
        t,x,y,z,qx,qy,qz,qw=map(float,l.split()[:8]); d[round(t,3)]=(x,y,2*math.atan2(qz,qw))
    return d
def comp(a,b):
    c,s=math.cos(a[2]),math.sin(a[2]); return (a[0]+c*b[0]-s*b[1],a[1]+s*b[0]+c*b[1],a[2]+b[2])
def inv(a):
    c,s=math.cos(a[2]),math.sin(a[2]); return (-(c*a[0]+s*a[1]),-(-s*a[0]+c*a[1]),-a[2])
def errs(d, f):
    gt=tum(d+'/trajectory_gt.tum'); e=tum(d+'/'+f); ts=sorted(t for t in e if t in gt)
    T=comp(gt[ts[0]],inv(e[ts[0]]))
    return [math.hypot(*(comp(T,e[t])[i]-gt[t][i] for i in (0,1))) for t in ts]
B=int(sys.argv[3]) if len(sys.argv)>3 else 100
cols=[(d,f) for d in sys.argv[1:3] for f in ('trajectory_est.tum','trajectory_online.tum')]
E=[errs(d,f) for d,f in cols]
print('stops      ' + '  '.join(f"{d.split('/')[-2][:8]}:{f[11:14]}" for d,f in cols))
n=min(len(e) for e in E)
for i in range(0,n,B):
    print(f"{i:5d}-{min(n,i+B)-1:5d} " + '  '.join(f"{sum(e[i:i+B])/len(e[i:i+B]):12.3f}" for e in E))
