import json,glob,os,math,sys
def load(d):
    out={}
    for s in glob.glob(d+'/runs/*/summary.json'):
        out[s.split('/')[-2]]=json.load(open(s))
    return out
base={}
for d in ['out/c_fix','out/c_s3','out/c_o_s2']: base.update(load(d))
new=load('out/s49/c_cwc')
names=sorted(new)
print('| run | end (before -> now) | coverage | ATE [m] | map precision above floor | path [m] | closures | collisions | min clearance [m] |')
print('|---|---|---|---|---|---|---|---|---|')
for k in names:
    a,b=base[k],new[k]
    print(f"| {k} | {a['termination_reason']} -> {b['termination_reason']} | {a['coverage_2d']:.3f} -> {b['coverage_2d']:.3f} | {a['ate_rmse_m']:.3f} -> {b['ate_rmse_m']:.3f} | {a['map_precision_above_floor']:.3f} -> {b['map_precision_above_floor']:.3f} | {a['path_length_m']:.0f} -> {b['path_length_m']:.0f} | {a['loop_closures']} -> {b['loop_closures']} | {b['collisions']} | {b['min_clearance_m']:.3f} |")
def stats(D,keys):
    c=[D[k]['coverage_2d'] for k in keys]; e=[D[k]['ate_rmse_m'] for k in keys]; p=[D[k]['map_precision_above_floor'] for k in keys]
    return f"coverage {sum(c)/len(c):.4f} / worst {min(c):.3f}; ATE {sum(e)/len(e):.4f} / worst {max(e):.3f} m; precision above floor {sum(p)/len(p):.3f}; path {sum(D[k]['path_length_m'] for k in keys):.0f} m; collisions {sum(D[k]['collisions'] for k in keys)}; min clearance {min(D[k]['min_clearance_m'] for k in keys):.3f}"
print()
print(len(names),'runs before:',stats(base,names))
print(len(names),'runs now:   ',stats(new,names))
def ratio(D):
    r=[]
    for k in names:
        if '_nbv_' in k and k.replace('_nbv_','_nearest_') in names:
            r.append(D[k]['path_length_m']/D[k.replace('_nbv_','_nearest_')]['path_length_m'])
    return r
rb=ratio(base); rn=ratio(new)
print(f"nbv/nearest path, {len(rn)} pairs: before {sum(rb)/len(rb):.3f} (worst {max(rb):.3f}), now {sum(rn)/len(rn):.3f} (worst {max(rn):.3f})")
for grp in ['omnirob_.*_s2','compact_.*_s3','omnirob_.*_s1']:
    import re
    ks=[k for k in names if re.search(grp,k)]
    if ks: print(grp, len(ks), 'before:', stats(base,ks)); print(grp, len(ks), 'now:   ', stats(new,ks))
