#!/usr/bin/env python3
"""Per-stop relative registration error: how much of each run's drift comes from
single bad steps vs many small ones. usage: steperr.py RUN_DIR [--top N]"""
import sys, math, csv
def tum(p):
    d = {}
    for l in open(p):
        if l.startswith('#') or not l.strip(): continue
        t,x,y,z,qx,qy,qz,qw = map(float, l.split()[:8])
        d[round(t,3)] = (x, y, 2*math.atan2(qz, qw))
    return d
def rel(a, b):
    dx, dy = b[0]-a[0], b[1]-a[1]; c, s = math.cos(a[2]), math.sin(a[2])
    return (c*dx+s*dy, -s*dx+c*dy, math.atan2(math.sin(b[2]-a[2]), math.cos(b[2]-a[2])))
run = sys.argv[1]; top = int(sys.argv[3]) if len(sys.argv) > 3 else 10
gt = tum(run+'/trajectory_gt.tum'); on = tum(run+'/trajectory_online.tum')
stops = {}
for r in csv.DictReader(open(run+'/stops.csv')):
    stops[round(float(r['timestamp']),3)] = r
ts = sorted(t for t in on if t in gt)
def comp(a,b):
    c,s_=math.cos(a[2]),math.sin(a[2]); return (a[0]+c*b[0]-s_*b[1], a[1]+s_*b[0]+c*b[1], a[2]+b[2])
def inv(a):
    c,s_=math.cos(a[2]),math.sin(a[2]); return (-(c*a[0]+s_*a[1]), -(-s_*a[0]+c*a[1]), -a[2])
T = comp(gt[ts[0]], inv(on[ts[0]]))
on = {t: comp(T, p) for t, p in on.items()}
rows = []
for i in range(1, len(ts)):
    a, b = ts[i-1], ts[i]
    rg = rel(gt[a], gt[b]); ro = rel(on[a], on[b])
    # error of the estimated step, expressed as the position error it adds 
    et = math.hypot(ro[0]-rg[0], ro[1]-rg[1]); ey = math.atan2(math.sin(ro[2]-rg[2]), math.cos(ro[2]-rg[2]))
    st = stops.get(b, {})
    # odometry step error
    if st and b in stops and a in stops:
        sa, sb = stops[a], stops[b]
        oa = (float(sa['odo_x']), float(sa['odo_y']), math.radians(float(sa['odo_yaw_deg'])))
        ob = (float(sb['odo_x']), float(sb['odo_y']), math.radians(float(sb['odo_yaw_deg'])))
        rod = rel(oa, ob); eo = math.hypot(rod[0]-rg[0], rod[1]-rg[1])
    else: eo = float('nan')
    errabs = math.hypot(on[b][0]-gt[b][0], on[b][1]-gt[b][1]) - math.hypot(on[a][0]-gt[a][0], on[a][1]-gt[a][1])
    rows.append((et, ey, b, st.get('stop','?'), math.hypot(rg[0],rg[1]), math.degrees(rg[2]), eo,
                 st.get('icp_goodness',''), st.get('icp_info_ratio',''), st.get('relocalized',''), st.get('icp_accepted',''), errabs))
tot = sum(r[0] for r in rows)
big = [r for r in rows if r[0] > 0.02]
inc = [r for r in rows if r[11] > 0.02]; dec = [r for r in rows if r[11] < -0.02]
print(f"  abs-error increments > 2 cm: {len(inc)} sum {sum(r[11] for r in inc):.3f}; decrements < -2 cm: {len(dec)} sum {sum(r[11] for r in dec):.3f}; all + {sum(r[11] for r in rows if r[11]>0):.3f} - {sum(r[11] for r in rows if r[11]<0):.3f}")
print(f"{run}: {len(rows)} steps, sum step err {tot:.3f} m; steps > 2 cm: {len(big)} sum {sum(r[0] for r in big):.3f}; > 5 cm: {sum(1 for r in rows if r[0]>0.05)}")
print(" err_m  err_deg stop  move_m turn_deg odo_err good ratio reloc acc d_abs_err")
for r in sorted(rows, key=lambda r: -r[11])[:top]:
    print(f" {r[0]:.3f} {math.degrees(r[1]):6.2f} {r[3]:>5} {r[4]:6.2f} {r[5]:7.1f} {r[6]:6.3f} {r[7]:>5} {r[8]:>6} {r[9]} {r[10]} {r[11]:.3f}")
