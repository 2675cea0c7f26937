#!/usr/bin/python3
"""Reads voxplore-explore logs of runs with [explore] seen_gate_verify = true
and prints, for gate fractions 0.3-1.0, how many checks the gate would have
answered (gated) and how many of those the full check called 'seen' (misses).

    gate_verify.py RUN_LOG...
"""
import re, sys
rows = []
for f in sys.argv[1:]:
    for line in open(f):
        m = re.search(r"seen gate: (\d+) of (\d+) frontier cells border (?:open )?unknown.*the frontier is (\w+)", line)
        if m and int(m[2]) > 0:
            rows.append((int(m[1]) / int(m[2]), m[3] == "seen"))
seen = sum(s for _, s in rows)
print(f"{len(rows)} checks, {seen} of them 'seen' by the full check")
print("| seen_gate_fraction | gated | misses |")
print("|---|---|---|")
for f in (0.3, 0.5, 0.7, 0.8, 0.9, 1.0):
    g = [s for x, s in rows if x >= f]
    print(f"| {f} | {len(g)} ({len(g) / len(rows):.0%}) | {sum(g)} |")
