import sys,math,json,os,csv
def load(f):
    P=[]
    for l in open(f):
        if l.startswith('#'): continue
        t,x,y,z,qx,qy,qz,qw=map(float,l.split())
        P.append((x,y,2*math.atan2(qz,qw)))
    return P
def ate(est,gt):
    E=load(est);G=load(gt)
    g0=G[0];e0=E[0];dth=g0[2]-e0[2];c,s=math.cos(dth),math.sin(dth)
    acc=0
    for e,g in zip(E,G):
        x=g0[0]+c*(e[0]-e0[0])-s*(e[1]-e0[1]); y=g0[1]+s*(e[0]-e0[0])+c*(e[1]-e0[1])
        acc+=(x-g[0])**2+(y-g[1])**2
    return math.sqrt(acc/len(E))
def closures(d):
    n=0;c=0
    for r in csv.DictReader(open(d+'/stops.csv')):
        if r['loop_closed']=='1':
            n+=1; c+= "'s candidate" in r['loop_message']
    return n,c
root=sys.argv[1]; runs=[l.strip() for l in open(sys.argv[2])]
A=[];B=[]
print('| run | ATE run [m] | ATE replay [m] | closures run -> replay (by a consistent match) |')
print('|---|---|---|---|')
for r in runs:
    name=os.path.basename(r); rp=os.path.join(root,name)
    if not os.path.exists(rp+'/trajectory_est.tum') or not os.path.exists(rp+'/summary.json'): continue
    a=ate(r+'/trajectory_est.tum',r+'/trajectory_gt.tum'); b=ate(rp+'/trajectory_est.tum',r+'/trajectory_gt.tum')
    n0,_=closures(r); n1,c1=closures(rp)
    A.append(a);B.append(b)
    print(f'| {name} | {a:.4f} | {b:.4f} | {n0} -> {n1} ({c1}) |')
if A:
    print(f'\n{len(A)} runs: mean ATE {sum(A)/len(A):.4f} -> {sum(B)/len(B):.4f} m, worst {max(A):.4f} -> {max(B):.4f} m; better {sum(b<a-0.001 for a,b in zip(A,B))}, worse {sum(b>a+0.001 for a,b in zip(A,B))}')
