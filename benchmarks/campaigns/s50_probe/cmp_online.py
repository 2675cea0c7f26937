import csv, json, subprocess, re, os
B={}
for r in csv.DictReader(open('/work/main/out/c_base/runs.csv')):
    B[(r['world'].split('/')[-2],r['robot'],r['strategy'],r['seed'])]=r
N=[]
try:
    N=list(csv.DictReader(open('/work/main/out/c_probe/runs.csv')))
except FileNotFoundError: pass
def loops(d):
    out=subprocess.run(['python3','/work/main/scripts/check_loops.py',d],capture_output=True,text=True).stdout
    m=re.search(r'(\d+) closure\(s\), (\d+) suspect',out); return (int(m.group(1)),int(m.group(2))) if m else (0,0)
print("| run | coverage_2d | ATE [m] | precision above floor | path [m] | min clearance [m] | collisions | closures / suspect | ends |")
print("|---|---|---|---|---|---|---|---|---|")
acc=[]
for r in N:
    k=(r['world'].split('/')[-2],r['robot'],r['strategy'],r['seed']); b=B[k]
    name=f"{k[0]}_{k[1]}_{k[2]}_s{k[3]}"
    lb=loops(f'/work/main/out/c_base/runs/{name}'); ln=loops(f'/work/main/out/c_probe/runs/{name}')
    f=lambda x,key: float(x[key])
    print(f"| {name} | {f(b,'coverage_2d'):.3f} -> {f(r,'coverage_2d'):.3f} | {f(b,'ate_rmse_m'):.3f} -> {f(r,'ate_rmse_m'):.3f} | {f(b,'map_precision_above_floor'):.3f} -> {f(r,'map_precision_above_floor'):.3f} | {f(b,'path_length_m'):.0f} -> {f(r,'path_length_m'):.0f} | {f(b,'min_clearance_m'):.3f} -> {f(r,'min_clearance_m'):.3f} | {b['collisions']} -> {r['collisions']} | {lb[0]}/{lb[1]} -> {ln[0]}/{ln[1]} | {b['termination_reason']} -> {r['termination_reason']} |")
    acc.append((b,r,lb,ln))
n=len(acc)
if n:
    m=lambda i,key: sum(float(x[i][key]) for x in acc)/n
    print(f"\n{n} runs: coverage {m(0,'coverage_2d'):.4f} -> {m(1,'coverage_2d'):.4f} (worst {min(float(x[0]['coverage_2d']) for x in acc):.3f} -> {min(float(x[1]['coverage_2d']) for x in acc):.3f}); ATE {m(0,'ate_rmse_m'):.4f} -> {m(1,'ate_rmse_m'):.4f} (worst {max(float(x[0]['ate_rmse_m']) for x in acc):.3f} -> {max(float(x[1]['ate_rmse_m']) for x in acc):.3f}); precision {m(0,'map_precision_above_floor'):.3f} -> {m(1,'map_precision_above_floor'):.3f}; path {sum(float(x[0]['path_length_m']) for x in acc):.0f} -> {sum(float(x[1]['path_length_m']) for x in acc):.0f} m; min clearance {min(float(x[1]['min_clearance_m']) for x in acc):.3f}; collisions {sum(int(x[1]['collisions']) for x in acc)}; suspect {sum(x[2][1] for x in acc)} -> {sum(x[3][1] for x in acc)}")
