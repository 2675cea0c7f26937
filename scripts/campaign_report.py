#!/usr/bin/env python3
"""Aggregates a campaign directory written by scripts/campaign.sh.

    scripts/campaign_report.py DIR

Reads DIR/jobs.tsv (the resolved spec; without it, every DIR/runs/*/run.json),
each run's run.json (campaign_run.sh), summary.json and coverage.csv
(voxplore-explore), the building.json beside a generated world, DIR/joblog and
DIR/invocations.tsv, and writes

  DIR/runs.csv   one row per spec line, in spec order; a run that failed or has
                 not run is a row with its error ("not run" without a run.json);
                 for a generated building, the doors the run went through (both
                 regions a door joins hold a ground-truth pose), all and those
                 under 0.90 m
  DIR/report.md  per (strategy, robot) means and worst cases, path per m2 of
                 floor, nbv/nearest path ratios paired per (world, robot, seed),
                 paths and times to 90 % / 97 % coverage, all runs, failures,
                 and what the campaign cost (for sizing a cluster)
  DIR/coverage_vs_path_<strategy>.png, DIR/path_per_m2_box.png (gnuplot;
                 data and script in DIR/plot_data/)

Python 3 standard library only; the plots need gnuplot (Debian gnuplot-nox)
and are skipped with a note in the report when it is missing. Never fails on
an empty campaign or missing files.
"""
import csv
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import time

THRESHOLDS = (0.90, 0.97)
JOB_COLUMNS = ("job", "name", "run_dir", "world_path", "robot", "strategy", "seed", "extra_args",
               "world", "spec_line")
# Keys of summary.json with a column of their own (in this order) before the
# coverage and area figures, and after them; every other key follows.
HEAD_KEYS = ("termination_reason", "steps", "stops", "path_length_m")
TAIL_KEYS = ("collisions", "min_clearance_m", "min_clearance_pose", "ate_rmse_m", "ate_online_rmse_m",
             "map_precision",
             "map_precision_above_floor", "sim_time_s", "compute_s")
COST_KEYS = ("wall_s", "cpu_s", "peak_rss_mb")


# --- reading ---------------------------------------------------------------

# Two runs "ended at equal coverage" when their coverage_2d differ by at most this.
EQUAL_COVERAGE = 0.05

def read_text(path):
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return f.read()
    except OSError:
        return None


_NONFINITE = re.compile(r'(?<=[:\[,\s])(-?)(nan|inf(?:inity)?)(?=\s*[,\]}])', re.IGNORECASE)


def read_json(path):
    """A JSON object, or None; tolerates the bare nan/inf C++ streams write."""
    text = read_text(path)
    if text is None:
        return None
    try:
        obj = json.loads(text)
    except ValueError:
        def repl(m):
            if m.group(2).lower() == "nan":
                return "NaN"
            return "-Infinity" if m.group(1) else "Infinity"
        try:
            obj = json.loads(_NONFINITE.sub(repl, text))
        except ValueError:
            return None
    return obj if isinstance(obj, dict) else None


def to_float(v):
    if isinstance(v, bool):
        return float(v)
    if isinstance(v, (int, float)):
        return float(v)
    try:
        return float(v)
    except (TypeError, ValueError):
        return None


def finite(v):
    f = to_float(v)
    return f if f is not None and math.isfinite(f) else None


def read_jobs(camp):
    jobs = []
    text = read_text(os.path.join(camp, "jobs.tsv"))
    if text is not None:
        for line in text.splitlines():
            cols = line.split("\t")
            if len(cols) < len(JOB_COLUMNS):
                cols += [""] * (len(JOB_COLUMNS) - len(cols))
            jobs.append(dict(zip(JOB_COLUMNS, cols)))
        return jobs
    # No jobs.tsv (not a campaign.sh directory): whatever runs/ holds.
    runs = os.path.join(camp, "runs")
    names = sorted(os.listdir(runs)) if os.path.isdir(runs) else []
    for i, name in enumerate(names, 1):
        rj = read_json(os.path.join(runs, name, "run.json")) or {}
        jobs.append({"job": str(i), "name": name, "run_dir": os.path.join(runs, name),
                     "world_path": rj.get("world", ""), "robot": rj.get("robot", ""),
                     "strategy": rj.get("strategy", ""), "seed": str(rj.get("seed", "")),
                     "extra_args": rj.get("extra_args", ""), "world": rj.get("world", ""),
                     "spec_line": rj.get("spec_line", "")})
    return jobs


def read_coverage_csv(path):
    """(path_length_m, sim_time_s, coverage_2d) per row of a coverage.csv."""
    rows = []
    try:
        with open(path, newline="", encoding="utf-8", errors="replace") as f:
            for r in csv.DictReader(f):
                p, t, c = (finite(r.get(k)) for k in ("path_length_m", "sim_time_s", "coverage_2d"))
                if p is not None and c is not None:
                    rows.append((p, t, c))
    except OSError:
        pass
    return rows


def first_reaching(series, x):
    for p, t, c in series:
        if c >= x:
            return p, t
    return None


# --- one row per run ----------------------------------------------------------

NARROW_DOOR_M = 0.90


def doors_passed(building, gt_path):
    """Doors of a generated building (building.json: regions with rects,
    doors joining two regions) that the run went through: both regions hold
    a ground-truth pose. All and those under NARROW_DOOR_M; empty when the
    world has no doors or the run no ground truth."""
    out = {"doors": None, "doors_passed": None, "doors_narrow": None, "doors_narrow_passed": None}
    doors = (building or {}).get("doors") or []
    regions = (building or {}).get("regions") or []
    if not doors or not regions or not os.path.exists(gt_path):
        return out
    seen = set()
    with open(gt_path) as f:
        for line in f:
            v = line.split()
            if not v or line.startswith("#") or len(v) < 3:
                continue
            x, y = float(v[1]), float(v[2])
            for reg in regions:
                if any(x0 <= x <= x1 and y0 <= y <= y1 for (x0, y0, x1, y1) in reg.get("rects", [])):
                    seen.add(reg.get("id"))
                    break
    passed = [all(k in seen for k in d.get("regions", [])) for d in doors]
    narrow = [float(d.get("width_m", 0)) < NARROW_DOOR_M for d in doors]
    out["doors"] = len(doors)
    out["doors_passed"] = sum(passed)
    out["doors_narrow"] = sum(narrow)
    out["doors_narrow_passed"] = sum(p and n for p, n in zip(passed, narrow))
    return out


def collect(camp, jobs):
    runs = []
    for job in jobs:
        rd = job["run_dir"] or os.path.join(camp, "runs", job["name"])
        if not os.path.isabs(rd):
            rd = os.path.join(camp, rd)
        rj = read_json(os.path.join(rd, "run.json"))
        summary = read_json(os.path.join(rd, "summary.json")) or {}
        series = read_coverage_csv(os.path.join(rd, "coverage.csv"))
        building = None
        if job["world_path"]:
            building = read_json(os.path.join(os.path.dirname(job["world_path"]), "building.json"))
        r = {"job": job, "run_dir": rd, "run": rj, "summary": summary, "series": series}
        if rj is None:
            r["error"] = "not run" + (" (unfinished: interrupted or under way)" if os.path.isdir(rd) else "")
            r["exit_status"] = None
        else:
            r["error"] = rj.get("error") or ""
            r["exit_status"] = rj.get("exit_status")
        r["ok"] = rj is not None and not r["error"] and bool(summary)
        if rj is not None and not r["error"] and not summary:
            r["error"] = "no summary.json"
        # Floor area: the summary's reachable floor, else the generator's floor area.
        path = finite(summary.get("path_length_m"))
        r["building_floor_area_m2"] = finite((building or {}).get("floor_area_m2"))
        r["layout"] = str((building or {}).get("layout") or "")
        area, source = None, ""
        if finite(summary.get("floor_reachable_m2")):
            area, source = finite(summary["floor_reachable_m2"]), "floor_reachable_m2"
        elif r["building_floor_area_m2"]:
            area, source = r["building_floor_area_m2"], "building.json floor_area_m2"
        r["path_per_m2"] = path / area if path is not None and area else None
        r.update(doors_passed(building, os.path.join(rd, "trajectory_gt.tum")))
        r["floor_source"] = source if r["path_per_m2"] is not None else ""
        for x in THRESHOLDS:
            hit = first_reaching(series, x) if series else None
            r["reach_%d" % round(100 * x)] = hit if hit else ("not reached" if series else None)
        cost = rj or {}
        r["wall_s"] = finite(cost.get("wall_s"))
        r["cpu_s"] = finite(cost.get("cpu_s"))
        r["peak_rss_mb"] = finite(cost.get("peak_rss_mb"))
        if r["peak_rss_mb"] is None:
            r["peak_rss_mb"] = finite(summary.get("peak_rss_mb"))
        runs.append(r)
    return runs


def summary_columns(runs):
    """(coverage keys, *_m2 keys, other keys) over every summary.json."""
    seen = []
    for r in runs:
        for k in r["summary"]:
            if k not in seen:
                seen.append(k)
    cov = [k for k in seen if k.startswith("coverage")]
    if "coverage_2d" in cov:
        cov.remove("coverage_2d")
    cov = ["coverage_2d"] + cov
    m2 = [k for k in seen if k.endswith("_m2") and k not in cov]
    fixed = set(HEAD_KEYS) | set(TAIL_KEYS) | set(COST_KEYS)
    other = [k for k in seen if k not in fixed and k not in cov and k not in m2]
    return cov, m2, other


def csv_value(v):
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else ("nan" if math.isnan(v) else ("inf" if v > 0 else "-inf"))
    if isinstance(v, (dict, list)):
        return json.dumps(v)
    return str(v)


def write_runs_csv(camp, runs):
    cov, m2, other = summary_columns(runs)
    header = (["world", "robot", "strategy", "seed", "extra_args", "exit_status", "error"]
              + list(HEAD_KEYS) + cov + m2
              + ["building_floor_area_m2", "layout", "path_per_m2", "floor_source"]
              + ["doors", "doors_passed", "doors_narrow", "doors_narrow_passed"] + list(TAIL_KEYS) + other
              + ["path_to_90_m", "time_to_90_s", "path_to_97_m", "time_to_97_s"]
              + list(COST_KEYS) + ["run_dir"])
    with open(os.path.join(camp, "runs.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for r in runs:
            j, s = r["job"], r["summary"]
            row = [j["world"], j["robot"], j["strategy"], j["seed"], j["extra_args"],
                   r["exit_status"], r["error"]]
            row += [s.get(k) for k in HEAD_KEYS] + [s.get(k) for k in cov] + [s.get(k) for k in m2]
            row += [r["building_floor_area_m2"], r["layout"], r["path_per_m2"], r["floor_source"]]
            row += [r["doors"], r["doors_passed"], r["doors_narrow"], r["doors_narrow_passed"]]
            row += [s.get(k) for k in TAIL_KEYS] + [s.get(k) for k in other]
            for x in (90, 97):
                hit = r["reach_%d" % x]
                row += list(hit) if isinstance(hit, tuple) else [hit, hit]
            row += [r[k] for k in COST_KEYS] + [os.path.relpath(r["run_dir"], camp)]
            w.writerow([csv_value(v) for v in row])
    return cov


# --- formatting ----------------------------------------------------------------

def fmt(v, key=""):
    if v is None:
        return "-"
    if isinstance(v, str):
        return v
    f = to_float(v)
    if f is None:
        return str(v)
    if not math.isfinite(f):
        return str(f)
    if key in ("steps", "stops", "collisions", "exit_status") or key.startswith("n_"):
        return "%d" % round(f)
    if key.startswith("coverage") or "precision" in key or key == "ratio":
        return "%.3f" % f
    if key in ("min_clearance_m", "ate_rmse_m", "path_per_m2"):
        return "%.3f" % f
    if key.endswith("_mb"):
        return "%.0f" % f
    if key.endswith("_m") or key.endswith("_s") or key.endswith("_m2"):
        return "%.1f" % f
    return "%.4g" % f


def md_cell(s):
    return str(s).replace("|", "\\|").replace("\n", " ")


def md_table(header, rows):
    out = ["| " + " | ".join(md_cell(h) for h in header) + " |",
           "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(md_cell(c) for c in row) + " |" for row in rows]
    return "\n".join(out)


def mean_worst(values, worst):
    vals = [v for v in (finite(x) for x in values) if v is not None]
    if not vals:
        return "-"
    return "%s / %s" % (fmt(statistics.fmean(vals), worst[1]), fmt(worst[0](vals), worst[1]))


# --- plots (gnuplot) ---------------------------------------------------------------

def quartiles(vals):
    """(q1, median, q3), the quartiles by the inclusive method (any n >= 1)."""
    v = sorted(vals)
    if len(v) == 1:
        return v[0], v[0], v[0]
    q1, med, q3 = statistics.quantiles(v, n=4, method="inclusive")
    return q1, med, q3


def gp_str(s):
    return "'" + str(s).replace("'", "''") + "'"


def safe(s):
    return re.sub(r"[^A-Za-z0-9._-]", "_", s) or "_"


def gnuplot_terminal():
    gp = shutil.which("gnuplot")
    if not gp:
        return None, None
    try:
        out = subprocess.run([gp, "-e", "set terminal"], capture_output=True, text=True,
                             timeout=30)
        terms = out.stdout + out.stderr
    except (OSError, subprocess.SubprocessError):
        return None, None
    if re.search(r"^\s*pngcairo\s", terms, re.M):
        return gp, "pngcairo size 1000,700 noenhanced font 'sans,10'"
    if re.search(r"^\s*png\s", terms, re.M):
        return gp, "png size 1000,700 noenhanced"
    return None, None


COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf")


def make_plots(camp, runs, strategies, groups):
    """Writes the PNGs; returns (list of (title, file), note)."""
    gp, term = gnuplot_terminal()
    if gp is None:
        return [], "gnuplot (Debian gnuplot-nox) with a png terminal was not found: no plots."
    data = os.path.join(camp, "plot_data")
    os.makedirs(data, exist_ok=True)
    robots = []
    for r in runs:
        if r["job"]["robot"] not in robots:
            robots.append(r["job"]["robot"])
    color = {rb: COLORS[i % len(COLORS)] for i, rb in enumerate(robots)}
    script = ["set terminal " + term, "set grid", "set key left top"]
    plots = []
    for st in strategies:
        png = "coverage_vs_path_%s.png" % safe(st)
        terms = []
        for rb in robots:
            series = [r["series"] for r in runs
                      if r["job"]["strategy"] == st and r["job"]["robot"] == rb and r["series"]]
            if not series:
                continue
            dat = os.path.join(data, "coverage_%s_%s.dat" % (safe(st), safe(rb)))
            with open(dat, "w") as f:
                f.write("# path_length_m coverage_2d; one block per run\n")
                for s in series:
                    f.writelines("%r %r\n" % (p, c) for p, _, c in s)
                    f.write("\n")
            terms.append("%s using 1:2 with lines lw 1.5 lc rgb %s title %s" % (
                gp_str(dat), gp_str(color[rb]), gp_str("%s, %d run%s" % (rb, len(series), "" if len(series) == 1 else "s"))))
        script += ["reset", "set terminal " + term, "set grid", "set key right bottom",
                   "set output " + gp_str(os.path.join(camp, png)),
                   "set title " + gp_str("coverage_2d against path length, strategy %s "
                                         "(one curve per run, from coverage.csv)" % st),
                   "set xlabel 'path length [m]'", "set ylabel 'coverage_2d'",
                   "set yrange [0:1.02]",
                   "set arrow from graph 0, first 0.9 to graph 1, first 0.9 nohead dt 2 lc rgb 'gray'",
                   "set arrow from graph 0, first 0.97 to graph 1, first 0.97 nohead dt 2 lc rgb 'gray'"]
        if terms:
            script.append("plot " + ", ".join(terms))
        else:
            script += ["set xrange [0:1]",
                       "set label 'no coverage.csv yet' at graph 0.5, graph 0.5 center",
                       "plot 2 notitle"]
        script.append("unset output")
        plots.append(("coverage_2d against path length, %s" % st, png))

    # Box plot of path per m2, one box per (strategy, robot) with values.
    png = "path_per_m2_box.png"
    dat = os.path.join(data, "path_per_m2.dat")
    blocks = []
    for (st, rb), rs in groups:
        vals = [r["path_per_m2"] for r in rs if r["ok"] and finite(r["path_per_m2"]) is not None]
        if vals:
            blocks.append(("%s %s (%d)" % (st, rb, len(vals)), rb, vals))
    script += ["reset", "set terminal " + term, "set grid ytics",
               "set output " + gp_str(os.path.join(camp, png)),
               "set title 'path length per m2 of floor, per strategy and robot (successful runs)'",
               "set ylabel 'path length / floor area [m/m2]'"]
    if blocks:
        # gnuplot 5.4's boxplot style draws no box for fewer than 4 values, so
        # the boxes are computed here (Tukey: quartiles, whiskers to the last
        # value within 1.5 IQR) and drawn as candlesticks; every value is drawn
        # as a point over its box.
        with open(dat, "w") as f:
            f.write("# x q1 whisker_low whisker_high q3 median; then (index 1) every value: x value\n")
            for i, (label, _, vals) in enumerate(blocks):
                f.write("# %d: %s\n" % (i + 1, label))
                q1, med, q3 = quartiles(vals)
                iqr = q3 - q1
                lo = min(v for v in vals if v >= q1 - 1.5 * iqr)
                hi = max(v for v in vals if v <= q3 + 1.5 * iqr)
                f.write("%d %r %r %r %r %r\n" % (i + 1, q1, lo, hi, q3, med))
            f.write("\n\n")
            for i, (_, _, vals) in enumerate(blocks):
                f.writelines("%d %r\n" % (i + 1, v) for v in vals)
        script += ["set style fill solid 0.3 border -1",
                   "set boxwidth 0.5",
                   "set yrange [0:*]",
                   "set xrange [0.3:%f]" % (len(blocks) + 0.7),
                   "set xtics (" + ", ".join("%s %d" % (gp_str(b[0]), i + 1)
                                             for i, b in enumerate(blocks)) + ")",
                   "unset key"]
        terms = []
        for i, (_, rb, _) in enumerate(blocks):
            sel = "($1 == %d ? $%%d : NaN)" % (i + 1)
            terms.append("%s index 0 using 1:%s:%s:%s:%s with candlesticks whiskerbars lc rgb %s" % (
                gp_str(dat), sel % 2, sel % 3, sel % 4, sel % 5, gp_str(color.get(rb, COLORS[0]))))
        terms.append("%s index 0 using 1:6:6:6:6 with candlesticks lw 2 lc rgb 'black'" % gp_str(dat))
        terms.append("%s index 1 using 1:2 with points pt 7 ps 0.7 lc rgb 'black'" % gp_str(dat))
        script.append("plot " + ", ".join(terms))
    else:
        script += ["set xrange [0:1]", "set yrange [0:1]", "unset xtics",
                   "set label 'no path per m2: needs floor_reachable_m2 in summary.json or a "
                   "building.json beside the world' at graph 0.5, graph 0.5 center",
                   "plot 2 notitle"]
    script.append("unset output")
    plots.append(("path per m2 of floor", png))

    gp_file = os.path.join(data, "plots.gp")
    with open(gp_file, "w") as f:
        f.write("\n".join(script) + "\n")
    try:
        res = subprocess.run([gp, gp_file], capture_output=True, text=True, timeout=300)
    except (OSError, subprocess.SubprocessError) as e:
        return [], "gnuplot failed (%s): no plots." % e
    note = ""
    if res.returncode != 0:
        note = "gnuplot exited %d: %s" % (res.returncode, res.stderr.strip().splitlines()[-1:])
    made = [(t, p) for t, p in plots if os.path.isfile(os.path.join(camp, p))]
    return made, note


# --- the report ------------------------------------------------------------------

# (key, how the worst case is taken, label)
GROUP_METRICS = (
    ("path_length_m", max, "path length [m]"),
    ("path_per_m2", max, "path per m2 of floor [m/m2]"),
    ("steps", max, "steps"),
    ("collisions", max, "collisions"),
    ("min_clearance_m", min, "min clearance [m]"),
    ("ate_rmse_m", max, "ATE RMSE [m]"),
    ("map_precision_above_floor", min, "map precision above floor"),
    ("compute_s", max, "compute [s]"),
    ("sim_time_s", max, "simulated time [s]"),
    ("wall_s", max, "wall [s]"),
    ("cpu_s", max, "CPU user+sys [s]"),
    ("peak_rss_mb", max, "peak RSS [MB]"),
)


def value(r, key):
    if key in r and key not in ("summary", "job", "run"):
        return r[key]
    return r["summary"].get(key)


def read_invocations(camp):
    rows = []
    try:
        with open(os.path.join(camp, "invocations.tsv"), newline="") as f:
            rows = list(csv.DictReader(f, delimiter="\t"))
    except OSError:
        pass
    return rows


def read_joblog_span(camp):
    starts, ends = [], []
    try:
        with open(os.path.join(camp, "joblog"), newline="") as f:
            for r in csv.DictReader(f, delimiter="\t"):
                s, d = finite(r.get("Starttime")), finite(r.get("JobRuntime"))
                if s is not None and d is not None:
                    starts.append(s)
                    ends.append(s + d)
    except OSError:
        pass
    return (min(starts), max(ends)) if starts else None


def write_report(camp, runs, cov_keys):
    L = []
    n = len(runs)
    ok = sum(r["ok"] for r in runs)
    not_run = sum(r["run"] is None for r in runs)
    failed = n - ok - not_run
    L.append("# Campaign report: %s" % os.path.basename(os.path.abspath(camp)))
    L.append("")
    L.append("Generated %s by `scripts/campaign_report.py` from `%s`: **%d runs, %d ok, %d failed, "
             "%d not run**. Every figure is from the runs' `summary.json` (voxplore-explore), "
             "`coverage.csv` and `run.json` (wall, CPU and peak RSS measured by `/usr/bin/time -v`); "
             "all rows are in [runs.csv](runs.csv)." % (
                 time.strftime("%Y-%m-%d %H:%M"), os.path.abspath(camp), n, ok, failed, not_run))
    L.append("")
    if n == 0:
        L.append("The campaign has no runs (an empty spec, or no `jobs.tsv` and nothing in `runs/`).")
        L.append("")
        with open(os.path.join(camp, "report.md"), "w") as f:
            f.write("\n".join(L))
        return

    strategies, group_keys = [], []
    for r in runs:
        st, rb = r["job"]["strategy"], r["job"]["robot"]
        if st not in strategies:
            strategies.append(st)
        if (st, rb) not in group_keys:
            group_keys.append((st, rb))
    robots = []
    for r in runs:
        if r["job"]["robot"] not in robots:
            robots.append(r["job"]["robot"])
    group_keys.sort(key=lambda k: (strategies.index(k[0]), robots.index(k[1])))
    groups = [(k, [r for r in runs if (r["job"]["strategy"], r["job"]["robot"]) == k])
              for k in group_keys]

    # Per (strategy, robot).
    L.append("## Per strategy and robot")
    L.append("")
    L.append("Cells are **mean / worst** over the successful runs (exit 0 with a summary.json; "
             "failed and unrun runs are only counted). Worst is the minimum for coverage, clearance "
             "and map precision, the maximum for everything else.")
    L.append("")
    header = ["", *["%s, %s" % k for k in group_keys]]
    rows = [["runs", *[str(len(rs)) for _, rs in groups]],
            ["failed", *[str(sum((not r["ok"]) and r["run"] is not None for r in rs)) for _, rs in groups]],
            ["not run", *[str(sum(r["run"] is None for r in rs)) for _, rs in groups]]]
    metrics = [(k, min, k) for k in cov_keys] + list(GROUP_METRICS)
    for key, worst, label in metrics:
        cells = []
        for _, rs in groups:
            okv = [value(r, key) for r in rs if r["ok"]]
            cell = mean_worst(okv, (worst, key))
            have = sum(finite(v) is not None for v in okv)
            if cell != "-" and have < len(okv):
                cell += " (%d of %d runs)" % (have, len(okv))
            cells.append(cell)
        if any(c != "-" for c in cells):
            rows.append([label, *cells])
    for x in (90, 97):
        for what, idx, unit in (("path", 0, "m"), ("sim. time", 1, "s")):
            cells = []
            for _, rs in groups:
                okr = [r for r in rs if r["ok"] and r["series"]]
                hits = [r["reach_%d" % x][idx] for r in okr if isinstance(r["reach_%d" % x], tuple)]
                hits = [h for h in hits if h is not None]
                if not okr:
                    cells.append("-")
                else:
                    cells.append("%s / %s (%d/%d reached)" % (
                        fmt(statistics.fmean(hits), "x_" + unit) if hits else "-",
                        fmt(max(hits), "x_" + unit) if hits else "-", len(hits), len(okr)))
            rows.append(["%s to %d %% coverage_2d [%s]" % (what, x, unit), *cells])
    L.append(md_table(header, rows))
    L.append("")
    L.append("Path and time to x %: the first row of the run's `coverage.csv` with coverage_2d >= x "
             "(its path_length_m and sim_time_s, simulated seconds); the mean and worst are over the "
             "runs that reached it.")
    L.append("")

    # Floor area source.
    sources = {}
    for r in runs:
        if r["floor_source"]:
            sources[r["floor_source"]] = sources.get(r["floor_source"], 0) + 1
    L.append("**Path per m2 of floor** = path_length_m / floor area, the floor area being "
             "`floor_reachable_m2` from the run's summary.json when it has that key, else "
             "`floor_area_m2` from the `building.json` beside a generated world. Here: %s." % (
                 ", ".join("%d runs from %s" % (c, s) for s, c in sorted(sources.items()))
                 if sources else "no run has either, so there is no path per m2"))
    L.append("")

    # By layout: the generated buildings only (their building.json names the layout).
    layouts = sorted({r["layout"] for r in runs if r["layout"]})
    if layouts:
        L.append("## By layout (generated buildings)")
        L.append("")
        L.append("Mean over the successful runs of each layout, strategy and robot (max for ATE and "
                 "collisions, min for clearance).")
        L.append("")
        lrow = []
        for lay in layouts:
            for (strategy, robot), _ in groups:
                rs = [r for r in runs if r["layout"] == lay and r["ok"]
                      and r["job"]["strategy"] == strategy and r["job"]["robot"] == robot]
                if not rs:
                    continue
                def vals(k):
                    return [v for v in (finite(value(r, k)) for r in rs) if v is not None]
                def agg(k, f):
                    v = vals(k)
                    return fmt(f(v), k) if v else "-"
                ppm = [r["path_per_m2"] for r in rs if r["path_per_m2"] is not None]
                lrow.append([lay, strategy, robot, str(len(rs)),
                             agg("coverage_2d", statistics.fmean), agg("ate_rmse_m", statistics.fmean),
                             agg("ate_rmse_m", max), agg("map_precision_above_floor", statistics.fmean),
                             "%.3f" % statistics.fmean(ppm) if ppm else "-",
                             agg("collisions", max), agg("min_clearance_m", min)])
        L.append(md_table(["layout", "strategy", "robot", "runs", "coverage_2d", "ATE mean [m]",
                           "ATE max [m]", "precision above floor", "path per m2", "collisions (max)",
                           "min clearance [m]"], lrow))
        L.append("")

    # Paired nbv / nearest.
    L.append("## nbv / nearest, paired")
    L.append("")
    pairs = {}
    for r in runs:
        j = r["job"]
        pairs.setdefault((j["world_path"] or j["world"], j["robot"], j["seed"], j["extra_args"]),
                         {})[j["strategy"]] = r
    prow, ratios = [], []
    by_robot, equal_cov = {}, {}
    for (world, robot, seed, extra), d in pairs.items():
        a, b = d.get("nbv"), d.get("nearest")
        if not a or not b:
            continue
        pa, pb = finite(value(a, "path_length_m")), finite(value(b, "path_length_m"))
        ratio = pa / pb if a["ok"] and b["ok"] and pa is not None and pb else None
        if ratio is not None:
            ratios.append(ratio)
            ca, cb = finite(value(a, "coverage_2d")), finite(value(b, "coverage_2d"))
            by_robot.setdefault(robot, []).append(ratio)
            if ca is not None and cb is not None and abs(ca - cb) <= EQUAL_COVERAGE:
                equal_cov.setdefault(robot, []).append(ratio)
        name = a["job"]["world"] + (" " + extra if extra else "")
        prow.append([name, robot, seed,
                     fmt(pa, "path_length_m") if a["ok"] else "failed",
                     fmt(pb, "path_length_m") if b["ok"] else "failed",
                     fmt(ratio, "ratio"),
                     fmt(value(a, "coverage_2d"), "coverage_2d") if a["ok"] else "-",
                     fmt(value(b, "coverage_2d"), "coverage_2d") if b["ok"] else "-"])
    if prow:
        L.append("Path length ratio nbv / nearest for every (world, robot, seed) run with both "
                 "strategies (below 1: nbv travelled less), with the coverage each reached; a ratio "
                 "needs both runs successful. %s" % (
                     "**Mean ratio %.3f, worst (largest) %.3f, best %.3f over %d pairs.**" % (
                         statistics.fmean(ratios), max(ratios), min(ratios), len(ratios))
                     if ratios else "No pair has two successful runs."))
        L.append("")
        # One run that goes nowhere (a ratio near 0 or in the hundreds) dominates a mean:
        # the medians, and the pairs that ended at about the same coverage, say more.
        srow = []
        for robot in sorted(by_robot):
            rs, eq = by_robot[robot], equal_cov.get(robot, [])
            srow.append([robot, str(len(rs)), "%.3f" % statistics.median(rs),
                         "%.3f" % statistics.fmean(rs), "%.3f" % max(rs),
                         "%d" % len(eq),
                         ("%.3f / %.3f / %.3f" % (statistics.median(eq), statistics.fmean(eq), max(eq)))
                         if eq else "-"])
        if srow:
            L.append(md_table(["robot", "pairs", "median nbv/nearest", "mean", "worst",
                               "pairs at equal coverage (within %.2f)" % EQUAL_COVERAGE,
                               "their median / mean / worst"], srow))
            L.append("")
        L.append(md_table(["world", "robot", "seed", "nbv path [m]", "nearest path [m]",
                           "nbv/nearest", "nbv coverage_2d", "nearest coverage_2d"], prow))
    else:
        L.append("No (world, robot, seed) was run with both nbv and nearest.")
    L.append("")

    # Plots.
    plots, note = make_plots(camp, runs, strategies, groups)
    L.append("## Plots")
    L.append("")
    if note:
        L.append(note)
        L.append("")
    for title, png in plots:
        L.append("[%s](%s)" % (title, png))
        L.append("")
        L.append("![%s](%s)" % (title, png))
        L.append("")
    L.append("Made with gnuplot from the data and script in `plot_data/` (rerun: `gnuplot "
             "plot_data/plots.gp`). Coverage curves: each run's `coverage.csv` rows, coverage_2d "
             "against path_length_m (one curve per run, colour by robot; dashed lines at 0.90 and "
             "0.97). Box plot: quartiles (inclusive method), median (thick line), whiskers to the "
             "last value within 1.5 IQR, every run a dot; computed here and drawn as gnuplot "
             "candlesticks, since gnuplot 5.4's boxplot style draws no box below 4 values.")
    L.append("")

    # Cost.
    L.append("## What the campaign cost")
    L.append("")
    inv = read_invocations(camp)
    inv_wall = sum(finite(i.get("wall_s")) or 0.0 for i in inv)
    span = read_joblog_span(camp)
    measured = [r for r in runs if r["run"] is not None]
    cpu = [r["cpu_s"] for r in measured if r["cpu_s"] is not None]
    wall = [r["wall_s"] for r in measured if r["wall_s"] is not None]
    rss = [r["peak_rss_mb"] for r in measured if r["peak_rss_mb"] is not None]
    jobs_used = sorted({i.get("jobs", "") for i in inv if i.get("jobs")})
    hosts_used = sorted({i.get("sshlogin", "") for i in inv if i.get("sshlogin")})
    crow = [
        ["campaign wall time (sum over %d campaign.sh calls, jobs %s, hosts %s)" % (
            len(inv), ",".join(jobs_used) or "-", ",".join(hosts_used) or "-"),
         "%.0f s (%.2f h)" % (inv_wall, inv_wall / 3600.0) if inv else "-"],
        ["first run start to last run end (joblog)",
         "%.0f s" % (span[1] - span[0]) if span else "-"],
        ["runs measured (ok and failed)", str(len(measured))],
        ["total wall of the runs", "%.0f s" % sum(wall) if wall else "-"],
        ["total CPU (user+sys)", "%.0f s (%.2f CPU-h)" % (sum(cpu), sum(cpu) / 3600.0) if cpu else "-"],
        ["CPU per run: mean / max", "%.1f / %.1f s" % (statistics.fmean(cpu), max(cpu)) if cpu else "-"],
        ["wall per run: mean / max", "%.1f / %.1f s" % (statistics.fmean(wall), max(wall)) if wall else "-"],
        ["peak RSS per run: mean / max", "%.0f / %.0f MB" % (statistics.fmean(rss), max(rss)) if rss else "-"],
    ]
    if cpu:
        crow.append(["1,000 runs like these would need",
                     "%.1f CPU-h, %.1f GB RAM per parallel run at most" % (
                         1000 * statistics.fmean(cpu) / 3600.0, max(rss) / 1024.0 if rss else 0)])
    L.append(md_table(["", ""], crow))
    L.append("")
    L.append("Wall, CPU and peak RSS of a run come from `/usr/bin/time -v` around voxplore-explore "
             "(the `timeout` wrapper included, negligible); the campaign wall time from "
             "`invocations.tsv`, written by `campaign.sh` at every call.")
    L.append("")

    # Failures.
    bad = [r for r in runs if not r["ok"]]
    L.append("## Failed and unrun runs")
    L.append("")
    if bad:
        L.append(md_table(["run", "exit status", "error"],
                          [[os.path.basename(r["run_dir"]), fmt(r["exit_status"], "exit_status"),
                            r["error"]] for r in bad]))
    else:
        L.append("None.")
    L.append("")

    # All runs.
    L.append("## All runs")
    L.append("")
    arows = []
    for r in runs:
        j, s = r["job"], r["summary"]
        reach = []
        for x in (90, 97):
            h = r["reach_%d" % x]
            reach.append("%s m, %s s" % (fmt(h[0], "x_m"), fmt(h[1], "x_s")) if isinstance(h, tuple)
                         else (h or "-"))
        arows.append([j["world"] + (" " + j["extra_args"] if j["extra_args"] else ""), j["robot"],
                      j["strategy"], j["seed"],
                      "ok" if r["ok"] else ("not run" if r["run"] is None else "FAILED (%s)" % fmt(r["exit_status"], "exit_status")),
                      s.get("termination_reason", "-"), fmt(s.get("steps"), "steps"),
                      fmt(s.get("path_length_m"), "path_length_m"),
                      fmt(s.get("coverage_2d"), "coverage_2d"), reach[0], reach[1],
                      fmt(r["path_per_m2"], "path_per_m2"), fmt(s.get("collisions"), "collisions"),
                      fmt(s.get("min_clearance_m"), "min_clearance_m"),
                      fmt(s.get("ate_rmse_m"), "ate_rmse_m"),
                      fmt(s.get("map_precision_above_floor"), "map_precision_above_floor"),
                      fmt(r["wall_s"], "wall_s"), fmt(r["cpu_s"], "cpu_s"),
                      fmt(r["peak_rss_mb"], "peak_rss_mb")])
    L.append(md_table(["world", "robot", "strategy", "seed", "status", "termination", "steps",
                       "path [m]", "coverage_2d", "to 90 %", "to 97 %", "path/m2", "collisions",
                       "min clearance [m]", "ATE [m]", "precision above floor", "wall [s]",
                       "CPU [s]", "peak RSS [MB]"], arows))
    L.append("")
    with open(os.path.join(camp, "report.md"), "w") as f:
        f.write("\n".join(L))


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) == 2 else 1
    camp = argv[1]
    if not os.path.isdir(camp):
        print("campaign_report.py: no campaign directory '%s'" % camp, file=sys.stderr)
        return 1
    runs = collect(camp, read_jobs(camp))
    cov = write_runs_csv(camp, runs)
    write_report(camp, runs, cov)
    ok = sum(r["ok"] for r in runs)
    print("campaign_report.py: %d runs (%d ok) -> %s, %s" % (
        len(runs), ok, os.path.join(camp, "runs.csv"), os.path.join(camp, "report.md")))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
