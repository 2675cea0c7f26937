#!/usr/bin/env python3
"""Cut a ground-grid test fixture (tests/data/*.txt, read by the footprint
tests' loadGroundFixture) out of a planning step a run kept.

    voxplore-plan -c RUN/params.ini -i RUN/plans/step_NNN.txt \
        --probe X,Y,YAW --probe-radius 60 > probe.txt
    scripts/ground_fixture.py probe.txt RUN/plans/step_NNN.txt "what happened" [RES] > tests/data/NAME.txt

The first probe in probe.txt gives G round the robot (its first panel:
'.' free, '#' occupied, '?' unknown; probe at the robot's pose, whose cell
is written free); the step file gives the robot's pose
and the swept path ('sw' lines), kept where they fall inside the crop. RES:
the planner's cell size ([projection]), 0.05 m unless given.
"""
import re
import sys


def main(argv):
    if len(argv) not in (4, 5):
        sys.stderr.write(__doc__)
        return 2
    probe_path, step_path, comment = argv[1:4]
    res = float(argv[4]) if len(argv) == 5 else 0.05
    with open(probe_path) as f:
        lines = f.read().splitlines()
    head = next((i for i, l in enumerate(lines) if "columns from x =" in l), None)
    if head is None:
        sys.stderr.write(f"{probe_path}: no probe (run voxplore-plan with --probe)\n")
        return 1
    m = re.search(r"columns from x = (-?[\d.]+), rows from y = (-?[\d.]+) down", lines[head])
    x_first, y_top = float(m.group(1)), float(m.group(2))
    rows = []
    for l in lines[head + 1:]:
        if " | " not in l:
            break
        rows.append(l.strip().split(" | ")[0])
    if not rows or len({len(r) for r in rows}) != 1:
        sys.stderr.write(f"{probe_path}: the probe's rows are missing or ragged\n")
        return 1
    with open(step_path) as f:
        step = [l.split() for l in f if l.strip() and not l.startswith("#")]
    robot = next((t for t in step if t[0] == "robot"), None)
    if robot is None:
        sys.stderr.write(f"{step_path}: no 'robot' line\n")
        return 1
    nx, ny = len(rows[0]), len(rows)
    x0 = x_first - 0.5 * res
    y0 = y_top + 0.5 * res - ny * res
    # '*' marks the probe's own cell (the robot's, probed at its pose): the
    # robot stands there, its cell is written free.
    code = {".": ".", "#": "O", "?": "U", "*": "."}
    print(f"# voxplore test fixture: {comment} {nx} x {ny} cells of {res} m, lower left corner "
          f"({x0:.3f}, {y0:.3f}); rows from the top (max y); . free, O occupied, U unknown; "
          f"then the swept path samples (sw x y yaw) inside the crop.")
    print(f"grid {nx} {ny} {res:.3f} {x0:.6f} {y0:.6f}")
    print(f"robot {robot[1]} {robot[2]} {robot[3]}")
    for r in rows:
        print("".join(code.get(c, "U") for c in r))
    for t in step:
        if t[0] == "sw":
            x, y = float(t[1]), float(t[2])
            if x0 <= x < x0 + nx * res and y0 <= y < y0 + ny * res:
                print(f"sw {t[1]} {t[2]} {t[3]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
