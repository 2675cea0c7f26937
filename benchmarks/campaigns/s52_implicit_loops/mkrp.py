#!/usr/bin/env python3
"""mkrp.py RUN/params.ini OUT.ini [key=value ...] : the run's SLAM sections, loop_closure overrides"""
import sys, re
keep = {'cloud','metaview','icp','octomap','loop_closure'}
out=[]; cur=None
for l in open(sys.argv[1]):
    m=re.match(r'\s*\[(\w+)\]', l)
    if m: cur=m.group(1)
    if cur in keep: out.append(l.rstrip('\n'))
txt='\n'.join(out)+'\n'
for kv in sys.argv[3:]:
    k,v=kv.split('=',1)
    if re.search(r'^%s\s*='%k, txt, re.M): txt=re.sub(r'^%s\s*=.*$'%k, f'{k} = {v}', txt, flags=re.M)
    else: txt=txt.replace('[loop_closure]', f'[loop_closure]\n{k} = {v}',1)
open(sys.argv[2],'w').write(txt)
