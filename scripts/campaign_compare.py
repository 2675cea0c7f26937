#!/usr/bin/env python3
"""Compares two campaigns run by scripts/campaign.sh, paired run by run.

    scripts/campaign_compare.py BEFORE AFTER [--labels "before,after"] [--out FILE.md]

BEFORE and AFTER are campaign directories (their runs.csv, written by
scripts/campaign_report.py) or runs.csv files; several joined with '+'
(A+B) make one campaign, a run in B replacing the same run in A (a part
redone). Runs are paired by (world file name and its folder, robot,
strategy, seed, extra arguments), so the two campaigns may live in different
folders and list their runs in any order.

Writes a markdown report (standard output, or --out) with, per strategy and
robot, the mean and worst of each figure before and after over the pairs
where both runs succeeded, how many pairs got better and worse, every
failure, and the pairs whose ATE or coverage changed the most. Worst is the
minimum for coverage, clearance and map precision, the maximum otherwise.
A mission-time table gives, per robot and strategy and over all pairs, the
simulated mission time summed before and after and its ratio, and the same
for the time each run took to reach coverage_2d 0.90 and 0.97 (pairs where
both runs reach it): the time at equal coverage (scan modes, issue 15).

Python 3 standard library only. Exit status 2 on bad arguments or an
unreadable runs.csv; a campaign with no common run is a report saying so.
"""
import argparse
import csv
import math
import os
import statistics
import sys

# (column, label, higher is better, decimals)
FIGURES = (
    ("ate_rmse_m", "ATE RMSE [m]", False, 3),
    ("map_precision_above_floor", "map precision above floor", True, 3),
    ("coverage_2d", "coverage_2d", True, 3),
    ("path_length_m", "path length [m]", False, 1),
    ("steps", "steps", False, 0),
    ("collisions", "collisions", False, 0),
    ("min_clearance_m", "min clearance [m]", True, 3),
    ("flagged_stops", "flagged stops", False, 0),
    ("compute_s", "compute [s]", False, 1),
    ("sim_time_s", "mission time, simulated [s]", False, 0),
    ("time_to_90_s", "time to coverage 0.90 [s]", False, 0),
    ("time_to_97_s", "time to coverage 0.97 [s]", False, 0),
)
# Times summed over the pairs (mission, and to equal coverage).
TIMES = (("sim_time_s", "mission"), ("time_to_90_s", "to coverage 0.90"),
         ("time_to_97_s", "to coverage 0.97"))
# A change smaller than this counts as neither better nor worse.
TOLERANCE = {"ate_rmse_m": 0.005, "map_precision_above_floor": 0.005, "coverage_2d": 0.005,
             "path_length_m": 1.0, "steps": 0.5, "collisions": 0.5, "min_clearance_m": 0.002,
             "flagged_stops": 0.5, "compute_s": 1.0, "sim_time_s": 1.0, "time_to_90_s": 1.0,
             "time_to_97_s": 1.0}


def read_one(path):
    if os.path.isdir(path):
        path = os.path.join(path, "runs.csv")
    try:
        with open(path, newline="", encoding="utf-8") as f:
            return path, list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"campaign_compare.py: cannot read '{path}': {e.strerror}")


def read_runs(spec):
    """A campaign, or several joined with '+': later runs replace earlier ones."""
    paths, by_key = [], {}
    for part in spec.split("+"):
        path, runs = read_one(part)
        paths.append(path)
        for r in runs:
            by_key[key(r)] = r
    return " + ".join(paths), list(by_key.values())


def key(row):
    world = row.get("world", "")
    # worlds/b3/building.world and /elsewhere/worlds/b3/building.world pair up.
    parts = world.replace("\\", "/").split("/")
    return ("/".join(parts[-2:]), row.get("robot", ""), row.get("strategy", ""),
            row.get("seed", ""), row.get("extra_args", ""))


def ok(row):
    return row.get("exit_status") == "0" and row.get("ate_rmse_m", "") not in ("", "nan")


def number(row, col):
    try:
        v = float(row.get(col, ""))
        return v if math.isfinite(v) else None
    except ValueError:
        return None


def paired(pairs, col):
    """(before, after) values of `col` over the pairs where both are numbers."""
    vals = [(number(b, col), number(r, col)) for b, r in pairs]
    return [(x, y) for x, y in vals if x is not None and y is not None]


def fmt(v, decimals):
    return "-" if v is None else f"{v:.{decimals}f}"


def worst(values, higher_better):
    return min(values) if higher_better else max(values)


def time_table(pairs, labels):
    """Summed times before and after, per robot and strategy and over all."""
    groups = {}
    for b, r in pairs:
        if ok(b) and ok(r):
            for g in ((r.get("robot", ""), r.get("strategy", "")), ("all", "")):
                groups.setdefault(g, []).append((b, r))
    if not groups:
        return []
    L = ["## Mission time (simulated)", "",
         f"Sums over the pairs with both runs successful: {labels[0]} -> {labels[1]} (ratio); the "
         "times to a coverage only over the pairs where both runs reach it (how many of all).", "",
         "| robot, strategy | pairs | " + " | ".join(t for _, t in TIMES) +
         " | per-run mission ratio: median, worst |", "|---|---|" + "---|" * (len(TIMES) + 1)]
    order = sorted(g for g in groups if g[0] != "all") + [("all", "")]
    for g in order:
        items = groups[g]
        cells = []
        for col, _ in TIMES:
            vals = paired(items, col)
            tb, ta = sum(x for x, _ in vals), sum(y for _, y in vals)
            reach = "" if col == "sim_time_s" else f" ({len(vals)} of {len(items)})"
            cells.append(f"{tb:.0f} -> {ta:.0f} s: **{ta / tb:.3f}**{reach}" if tb > 0 else "-")
        ratios = sorted(y / x for x, y in paired(items, "sim_time_s") if x)
        per_run = f"{statistics.median(ratios):.3f}, {ratios[-1]:.3f}" if ratios else "-"
        L.append(f"| {' '.join(x for x in g if x)} | {len(items)} | " + " | ".join(cells) + f" | {per_run} |")
    return L + [""]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--labels", default="before,after", help="two names, comma separated")
    ap.add_argument("--out", help="write the report here (default: standard output)")
    a = ap.parse_args()
    labels = a.labels.split(",")
    if len(labels) != 2 or not all(labels):
        ap.error("--labels needs two names, comma separated")
    path_b, runs_b = read_runs(a.before)
    path_a, runs_a = read_runs(a.after)
    by_b = {key(r): r for r in runs_b}
    pairs = [(by_b[key(r)], r) for r in runs_a if key(r) in by_b]

    L = [f"# Campaign comparison: {labels[0]} vs {labels[1]}", "",
         f"{labels[0]}: `{path_b}` ({len(runs_b)} runs); {labels[1]}: `{path_a}` ({len(runs_a)} runs); "
         f"{len(pairs)} paired by world, robot, strategy, seed and extra arguments.", ""]
    if not pairs:
        L.append("No run is in both campaigns.")
    groups = {}
    for b, r in pairs:
        groups.setdefault((r.get("strategy", ""), r.get("robot", "")), []).append((b, r))
    for (strategy, robot), items in sorted(groups.items()):
        both = [(b, r) for b, r in items if ok(b) and ok(r)]
        L += [f"## {strategy}, {robot}", "",
              f"{len(items)} pairs, {len(both)} with both runs successful. Cells: mean / worst.", "",
              f"| figure | {labels[0]} | {labels[1]} | better / worse / same |", "|---|---|---|---|"]
        for col, label, higher, dec in FIGURES:
            vals = paired(both, col)
            if not vals:
                continue
            xb = [x for x, _ in vals]
            xa = [y for _, y in vals]
            tol = TOLERANCE.get(col, 0)
            better = sum(1 for x, y in vals if (y - x > tol if higher else x - y > tol))
            worse = sum(1 for x, y in vals if (x - y > tol if higher else y - x > tol))
            L.append(f"| {label} | {fmt(sum(xb) / len(xb), dec)} / {fmt(worst(xb, higher), dec)} | "
                     f"{fmt(sum(xa) / len(xa), dec)} / {fmt(worst(xa, higher), dec)} | "
                     f"{better} / {worse} / {len(vals) - better - worse} |")
        failed = [(b, r) for b, r in items if not (ok(b) and ok(r))]
        if failed:
            L += ["", "Failed in one of them:"]
            for b, r in failed:
                which = [labels[i] for i, x in enumerate((b, r)) if not ok(x)]
                err = (r if not ok(r) else b).get("error", "") or "no summary"
                L.append(f"- {key(r)[0]}: {' and '.join(which)} ({err[:120]})")
        L.append("")
    L += time_table(pairs, labels)
    # The largest changes, for a closer look.
    changes = []
    for b, r in pairs:
        if ok(b) and ok(r):
            d = number(r, "ate_rmse_m") - number(b, "ate_rmse_m")
            c = (number(r, "coverage_2d") or 0) - (number(b, "coverage_2d") or 0)
            changes.append((abs(d) + abs(c), key(r), b, r, d, c))
    changes.sort(key=lambda x: -x[0])
    if changes:
        L += ["## Largest changes (ATE, coverage_2d)", "",
              f"| world | robot | strategy | ATE {labels[0]} | ATE {labels[1]} | coverage {labels[0]} | "
              f"coverage {labels[1]} | end {labels[1]} |", "|---|---|---|---|---|---|---|---|"]
        for _, k, b, r, d, c in changes[:12]:
            L.append(f"| {k[0]} | {k[1]} | {k[2]} | {fmt(number(b, 'ate_rmse_m'), 3)} | "
                     f"{fmt(number(r, 'ate_rmse_m'), 3)} | {fmt(number(b, 'coverage_2d'), 3)} | "
                     f"{fmt(number(r, 'coverage_2d'), 3)} | {r.get('termination_reason', '')} |")
    text = "\n".join(L) + "\n"
    if a.out:
        with open(a.out, "w", encoding="utf-8") as f:
            f.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
