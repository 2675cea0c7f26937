#!/usr/bin/env python3
"""Judges the path-window stagnation end ([explore] stagnation_path_m,
stagnation_path_min_gain_m2) offline, on the coverage.csv of runs made
without it (or with a longer window).

The rule only ends a run earlier and a run is deterministic up to that step,
so cutting a run's coverage.csv at the first step where the rule fires gives
exactly the run with the rule (checked: b10 compact nbv re-run with 150 m /
5 m^2 ended at the predicted step, path and coverage). The check mirrors
ExplorationLoop::pathStagnationGain(): after each planning step, the free
floor known in G (known_floor_m2) against the latest earlier step at least
the window of metres driven back.

Usage:
  scripts/stagnation_offline.py CAMPAIGN_DIR_OR_CSV_DIR... [--window 100,150,200]
                                [--gain 2,5,8] [--runs] [--guard]
A directory holding runs/*/coverage.csv (scripts/campaign.sh) or *.csv files
(benchmarks/campaigns/*/coverage/). Prints, per (window, gain): runs where the
rule fires, the largest coverage_2d loss and the run, the worst coverage, the
path summed over all runs before and after; --runs adds one line per run for
the first (window, gain).
"""
import argparse
import csv
import glob
import itertools
import os
import sys


def load(dirs):
    runs = []
    for d in dirs:
        files = sorted(glob.glob(os.path.join(d, 'runs', '*', 'coverage.csv')))
        names = [os.path.basename(os.path.dirname(f)) for f in files]
        if not files:
            files = sorted(glob.glob(os.path.join(d, '*.csv')))
            names = [os.path.splitext(os.path.basename(f))[0] for f in files]
        if not files:
            sys.exit('stagnation_offline.py: no runs/*/coverage.csv nor *.csv in %s' % d)
        for name, f in zip(names, files):
            with open(f) as fh:
                reader = csv.DictReader(fh)
                rows = list(reader)
            if 'known_floor_m2' not in (reader.fieldnames or []):
                sys.exit('stagnation_offline.py: %s has no known_floor_m2 column '
                         '(runs before the twenty-fourth session)' % f)
            if rows:
                runs.append((name, rows))
    return runs


def fires(rows, window, gain, guard=False):
    """The index of the row where the rule ends the run, or None. guard:
    not at a step with a new frontier ([explore]
    stagnation_new_frontier_guard, coverage.csv's new_frontiers)."""
    path = [float(r['path_length_m']) for r in rows]
    floor = [float(r['known_floor_m2']) for r in rows]
    j = 0
    for i, r in enumerate(rows):
        if r.get('done', 'no') != 'no':
            return None  # the planner ended the run first
        while j + 1 < i and path[j + 1] <= path[i] - window:
            j += 1
        if j < i and path[i] - path[j] >= window and floor[i] - floor[j] < gain:
            if guard and int(r['new_frontiers']) > 0:
                continue
            return i
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('dirs', nargs='+')
    ap.add_argument('--window', default='100,150,200', help='windows [m], comma separated')
    ap.add_argument('--gain', default='2,5,8', help='minimum gains [m^2], comma separated')
    ap.add_argument('--runs', action='store_true', help='one line per run (first window, gain)')
    ap.add_argument('--guard', action='store_true',
                    help='no end at a step with a new frontier (stagnation_new_frontier_guard)')
    a = ap.parse_args()
    runs = load(a.dirs)
    if a.guard:
        for name, rows in runs:
            if 'new_frontiers' not in rows[0]:
                sys.exit('stagnation_offline.py: %s has no new_frontiers column '
                         '(runs before the twenty-fifth session); --guard needs it' % name)
    windows = [float(x) for x in a.window.split(',')]
    gains = [float(x) for x in a.gain.split(',')]
    print('| window [m] | gain [m^2] | runs ended | largest loss | worst coverage | path before -> after [m] |')
    print('|---|---|---|---|---|---|')
    for w, g in itertools.product(windows, gains):
        fired, loss, worst, cov_min, p0, p1 = 0, 0.0, '', 9.0, 0.0, 0.0
        for name, rows in runs:
            i = fires(rows, w, g, a.guard)
            end = rows[-1] if i is None else rows[i]
            c0, c1 = float(rows[-1]['coverage_2d']), float(end['coverage_2d'])
            fired += i is not None
            if c0 - c1 > loss:
                loss, worst = c0 - c1, '%s %.3f -> %.3f' % (name, c0, c1)
            cov_min = min(cov_min, c1)
            p0 += float(rows[-1]['path_length_m'])
            p1 += float(end['path_length_m'])
        print('| %g | %g | %d of %d | %.3f %s | %.3f | %.0f -> %.0f |'
              % (w, g, fired, len(runs), loss, worst, cov_min, p0, p1))
    if a.runs:
        w, g = windows[0], gains[0]
        print('\nper run, window %g m, gain %g m^2:' % (w, g))
        for name, rows in runs:
            i = fires(rows, w, g, a.guard)
            end = rows[-1] if i is None else rows[i]
            print('%-50s coverage %.3f -> %.3f  path %6.0f -> %6.0f  %s'
                  % (name, float(rows[-1]['coverage_2d']), float(end['coverage_2d']),
                     float(rows[-1]['path_length_m']), float(end['path_length_m']),
                     'stagnation at step %s' % end['step'] if i is not None
                     else (rows[-1]['done'] if rows[-1]['done'] != 'no' else 'did not end (a limit)')))


if __name__ == '__main__':
    main()
