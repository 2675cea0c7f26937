#!/usr/bin/env python3
"""mkrp.py RUN/params.ini OUT.ini [section.key=value ...]: the run's SLAM
sections ([cloud] [metaview] [icp] [octomap] [loop_closure]) with overrides;
a key the section does not hold yet is added at its top."""
import re
import sys

keep = {'cloud', 'metaview', 'icp', 'octomap', 'loop_closure'}
sections, cur = {}, None
for line in open(sys.argv[1]):
    m = re.match(r'\s*\[(\w+)\]', line)
    if m:
        cur = m.group(1)
        if cur in keep:
            sections[cur] = []
        continue
    if cur in keep:
        sections[cur].append(line.rstrip('\n'))
for kv in sys.argv[3:]:
    sk, v = kv.split('=', 1)
    sec, k = sk.split('.', 1)
    if sec not in sections:
        sys.exit(f'mkrp.py: no section [{sec}] kept from {sys.argv[1]}')
    lines = sections[sec]
    for i, line in enumerate(lines):
        if re.match(r'\s*%s\s*=' % re.escape(k), line):
            lines[i] = f'{k} = {v}'
            break
    else:
        lines.insert(0, f'{k} = {v}')
with open(sys.argv[2], 'w') as f:
    for sec, lines in sections.items():
        f.write(f'[{sec}]\n' + '\n'.join(lines) + '\n')
