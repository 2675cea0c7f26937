#!/usr/bin/env python3
"""Online estimate against the final (loop-closed) poses, and "implicit closures", per run of a campaign.

    implicit_closures.py CAMPAIGN_DIR

For every stop k of every run (CAMPAIGN_DIR/runs/*/stops.csv with
trajectory_gt.tum), the online estimate of stop k is the next stop's
prediction minus the odometry increment (SlamIcp predicts from its estimate
plus odometry), against the truth aligned at the first stop; the final error
is stops.csv's corrected x, y. An "implicit closure" is a drop of the online
error by at least 0.08 m within 60 stops with no loop closed in between: the
registration against the metaview carried the estimate back onto an older
map by itself. Prints per run the RMS of both and the events (start stop,
end stop, error before, error after). Python 3 standard library only.
"""
import csv,math,sys,glob,os
def load(f):
    out=[]
    for l in open(f):
        if l.startswith('#') or not l.strip(): continue
        v=list(map(float,l.split())); out.append((v[1],v[2],2*math.atan2(v[6],v[7])))
    return out
def comp(a,b):
    c,s=math.cos(a[2]),math.sin(a[2]); return (a[0]+c*b[0]-s*b[1],a[1]+s*b[0]+c*b[1],a[2]+b[2])
def inv(a):
    c,s=math.cos(a[2]),math.sin(a[2]); return (-c*a[0]-s*a[1], s*a[0]-c*a[1], -a[2])
P=lambda r,p:(float(r[p+'x']),float(r[p+'y']),math.radians(float(r[p+'yaw_deg'])))
tot=0
for R in sorted(glob.glob(sys.argv[1]+'/runs/*')):
    rows=list(csv.DictReader(open(R+'/stops.csv'))); g=load(R+'/trajectory_gt.tum'); x0,y0,t0=g[0]
    def gl(i):
        gx,gy,gt=g[i]; dx,dy=gx-x0,gy-y0; c,s=math.cos(-t0),math.sin(-t0); return c*dx-s*dy,s*dx+c*dy
    on=[];fin=[]
    for k in range(len(rows)-1):
        r,n=rows[k],rows[k+1]
        inc=comp(inv(P(r,'odo_')),P(n,'odo_')); e=comp(P(n,'pred_'),inv(inc)); gx,gy=gl(k)
        on.append(math.hypot(e[0]-gx,e[1]-gy)); fin.append(math.hypot(float(r['x'])-gx,float(r['y'])-gy))
    closed=[int(r['loop_closed']) for r in rows]
    # implicit closures: online error drops by >= 0.08 within 60 stops, no closure in window
    ev=[];k=0
    while k<len(on)-1:
        hi=on[k]; j=k+1
        found=False
        while j<min(len(on),k+60):
            if hi-on[j]>=0.08 and not any(closed[k:j+1]): found=True;break
            j+=1
        if found: ev.append((k,j,round(hi,3),round(on[j],3))); k=j
        else: k+=1
    rm=lambda a:math.sqrt(sum(x*x for x in a)/len(a))
    tot+=len(ev)
    print(os.path.basename(R), 'online %.3f final %.3f'%(rm(on),rm(fin)), 'implicit', len(ev), ev[:4])
print('total',tot)
