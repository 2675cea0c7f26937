#!/usr/bin/env python3
"""Checks every loop closure of voxplore runs against ground truth.

    scripts/check_loops.py DIR [DIR ...] [--max-error M] [--out FILE.md] [--fail-on-suspect]

Each DIR is a run directory (stops.csv and trajectory_gt.tum, as written by
voxplore-explore, voxplore-replay beside a recorded ground truth, or a
campaign run) or a campaign directory (its runs/*/ are taken).

A run's stops.csv holds the final (corrected) pose of every stop, and its
trajectory_gt.tum the true pose of the same stops in the world frame; the
map frame is the first stop's true pose. For every stop that closed a loop
(loop_closed = 1), the report gives the correction, how far the graph
moved, the final position error of the closing stop and of the old stop it
was joined to, and the error of the loop itself: the closing stop's pose
relative to the joined one, estimated against true. A right closure gets
that relative pose to within the registration's centimetres, even where the
old stop itself had drifted; a false one (a look-alike room, an aliased
corridor) builds the mistake into the graph, a room or a feature period
off. A closure whose relative error exceeds --max-error (default 0.15 m) or
--max-yaw (default 3 deg) is reported as SUSPECT.

Writes a markdown report (standard output, or --out). Exit status 2 on bad
arguments or an unreadable run (naming the file), 1 with --fail-on-suspect
when a closure is suspect, 0 otherwise. Python 3 standard library only.
"""
import argparse
import csv
import math
import os
import sys


def die(msg):
    print("check_loops.py: " + msg, file=sys.stderr)
    sys.exit(2)


def read_tum(path):
    """(x, y, yaw) per line of a TUM file (t x y z qx qy qz qw)."""
    poses = []
    try:
        with open(path) as f:
            for n, line in enumerate(f, 1):
                line = line.strip()
                if not line or line.startswith("#"):
                    continue
                v = line.split()
                if len(v) != 8:
                    die("%s:%d: expected 8 columns (t x y z qx qy qz qw), got %d" % (path, n, len(v)))
                x, y = float(v[1]), float(v[2])
                qx, qy, qz, qw = (float(c) for c in v[4:8])
                yaw = math.atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz))
                poses.append((x, y, yaw))
    except OSError as e:
        die("%s: %s" % (path, e.strerror))
    except ValueError as e:
        die("%s: %s" % (path, e))
    return poses


def relative(a, b):
    """b expressed in the frame of a (2D poses)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    c, s = math.cos(a[2]), math.sin(a[2])
    return (c * dx + s * dy, -s * dx + c * dy, b[2] - a[2])


def run_dirs(paths):
    out = []
    for p in paths:
        if os.path.isfile(os.path.join(p, "stops.csv")):
            out.append(p)
        elif os.path.isdir(os.path.join(p, "runs")):
            found = sorted(os.path.join(p, "runs", d) for d in os.listdir(os.path.join(p, "runs")))
            out.extend(d for d in found if os.path.isfile(os.path.join(d, "stops.csv")))
        else:
            die("%s: neither a run directory (stops.csv) nor a campaign directory (runs/)" % p)
    return out


def check_run(d, max_error, max_yaw):
    stops_path = os.path.join(d, "stops.csv")
    gt_path = os.path.join(d, "trajectory_gt.tum")
    try:
        with open(stops_path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        die("%s: %s" % (stops_path, e.strerror))
    if rows and ("loop_closed" not in rows[0] or "x" not in rows[0]):
        die("%s: no loop_closed / x column (not a voxplore stops.csv?)" % stops_path)
    closing = [r for r in rows if r.get("loop_closed") == "1"]
    if not closing:
        return [], None
    if not os.path.isfile(gt_path):
        return [], "%s: %d closure(s) but no trajectory_gt.tum: not checked" % (d, len(closing))
    gt = read_tum(gt_path)
    if len(gt) != len(rows):
        die("%s: %d ground-truth poses for %d stops" % (gt_path, len(gt), len(rows)))
    by_stop = {int(r["stop"]): i for i, r in enumerate(rows)}

    def error(i):
        t = relative(gt[0], gt[i])
        return math.hypot(float(rows[i]["x"]) - t[0], float(rows[i]["y"]) - t[1])

    def est(i):
        return (float(rows[i]["x"]), float(rows[i]["y"]), math.radians(float(rows[i]["yaw_deg"])))

    def loop_error(i, j):
        e, t = relative(est(j), est(i)), relative(gt[j], gt[i])
        dyaw = math.degrees(math.atan2(math.sin(e[2] - t[2]), math.cos(e[2] - t[2])))
        return math.hypot(e[0] - t[0], e[1] - t[1]), abs(dyaw)

    out = []
    for r in closing:
        i = by_stop[int(r["stop"])]
        j = by_stop.get(int(r["loop_with_stop"])) if r.get("loop_with_stop") else None
        e_new = error(i)
        e_old = error(j) if j is not None else float("nan")
        e_loop, e_yaw = loop_error(i, j) if j is not None else (float("nan"), float("nan"))
        suspect = j is None or e_loop > max_error or e_yaw > max_yaw
        out.append({
            "run": d, "stop": r["stop"], "with": r.get("loop_with_stop", ""),
            "correction": float(r.get("loop_correction_m") or 0),
            "shift": float(r.get("graph_shift_max_m") or 0),
            "e_new": e_new, "e_old": e_old, "e_loop": e_loop, "e_yaw": e_yaw, "suspect": suspect,
        })
    return out, None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--max-error", type=float, default=0.15,
                    help="a loop whose relative pose is off by more than this is suspect [m]")
    ap.add_argument("--max-yaw", type=float, default=3.0,
                    help="... or by more than this yaw [deg]")
    ap.add_argument("--out", help="write the report here (default: standard output)")
    ap.add_argument("--fail-on-suspect", action="store_true", help="exit 1 when a closure is suspect")
    a = ap.parse_args()
    if not a.max_error > 0 or not a.max_yaw > 0:
        die("--max-error and --max-yaw must be positive")
    closures, notes, runs = [], [], run_dirs(a.dirs)
    for d in runs:
        c, note = check_run(d, a.max_error, a.max_yaw)
        closures.extend(c)
        if note:
            notes.append(note)
    suspect = [c for c in closures if c["suspect"]]
    lines = ["# Loop closures against ground truth", "",
             "%d run(s), %d closure(s), %d suspect (the loop's relative pose off by over %.2f m or %.1f deg)."
             % (len(runs), len(closures), len(suspect), a.max_error, a.max_yaw), ""]
    if closures:
        lines += ["| run | stop | joined to | correction [m] | graph moved [m] | error closing stop [m] | error joined stop [m] | loop error [m] / [deg] | |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for c in closures:
            lines.append("| %s | %s | %s | %.3f | %.3f | %.3f | %.3f | %.3f / %.2f | %s |" % (
                os.path.basename(os.path.normpath(c["run"])), c["stop"], c["with"], c["correction"],
                c["shift"], c["e_new"], c["e_old"], c["e_loop"], c["e_yaw"],
                "SUSPECT" if c["suspect"] else "ok"))
        worst = max(closures, key=lambda c: c["e_loop"] if c["e_loop"] == c["e_loop"] else 1e9)
        lines += ["", "Largest loop error: %.3f m (%s, stop %s)." % (
            worst["e_loop"], os.path.basename(os.path.normpath(worst["run"])), worst["stop"])]
    for n in notes:
        lines.append("- " + n)
    text = "\n".join(lines) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    sys.exit(1 if a.fail_on_suspect and suspect else 0)


if __name__ == "__main__":
    main()
