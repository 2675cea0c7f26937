import glob, os, math
tot=held=slid=0; lines=[]
for d in sorted(glob.glob('/work/main/out/rp1/*/')):
    r=os.path.basename(d.rstrip('/'))
    if not os.path.exists(d+'summary.json'): continue
    for l in open(d+'replay.err'):
        if l.startswith('PROBEDBG'):
            f=l.split(); st=int(f[2]); ratio=float(f[4]); worst=float(f[6]); corr=float(f[8])
            if ratio>=0.3 or corr<=0.03: continue
            tot+=1; ok=worst<=0.025; held+=ok; slid+=not ok
            lines.append(f"| {r} | {st} | {ratio:.3f} | {corr:.3f} | {worst:.4f} | {'holds' if ok else 'slides: no loop'} |")
print("| run | stop | information ratio | correction [m] | probes end up to [m] | |")
print("|---|---|---|---|---|---|")
print('\n'.join(lines))
print(f"\n{tot} correcting matches probed (ratio < 0.3, correction > 0.03 m): {held} held, {slid} slid.")
