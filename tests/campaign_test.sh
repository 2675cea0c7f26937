#!/usr/bin/env bash
# Campaign.ResumeAndReport: scripts/campaign.sh end to end on dlr_test_room.
#   tests/campaign_test.sh [BIN_DIR]      (default: REPO/build/bin)
# A 3-line spec (omnirob nbv seed 1, omnirob nearest seed 1, a world file that
# does not exist) through GNU parallel with --sshlogin : (parallel's ssh code
# path, on this machine) and --max-steps 1, then checks runs.csv, report.md and
# the plots; runs campaign.sh again on the same directory and checks that it
# redid nothing. About 15 s on 2 cores. Fails (non-zero) on any check.
set -euo pipefail

REPO=$(cd "$(dirname "$0")/.." && pwd)
BIN=$(realpath -m -- "${1:-$REPO/build/bin}")
[ -x "$BIN/voxplore-explore" ] || { echo "FAIL: no voxplore-explore in $BIN" >&2; exit 1; }
for t in parallel gnuplot python3; do
  command -v "$t" >/dev/null || { echo "FAIL: $t is missing (scripts/install_deps.sh)" >&2; exit 1; }
done

TMP=$(mktemp -d "${TMPDIR:-/tmp}/campaign_test.XXXXXX")
ok=0
cleanup() { if [ "$ok" -eq 1 ]; then rm -rf "$TMP"; else echo "campaign_test: outputs kept in $TMP" >&2; fi; }
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
# parallel keeps state in $PARALLEL_HOME (default ~/.parallel): keep the test's own.
export PARALLEL_HOME="$TMP/parallel_home"

# WORLD relative to the repository root (not found beside the spec).
cat > "$TMP/spec.txt" <<'EOF'
# campaign_test.sh
simulated_worlds/dlr_test_room.world omnirob nbv 1
simulated_worlds/dlr_test_room.world omnirob nearest 1   # the baseline

no_such_dir/no_such_world.world omnirob nbv 1
EOF
OUT="$TMP/campaign"
campaign() {
  "$REPO/scripts/campaign.sh" --spec "$TMP/spec.txt" --out "$OUT" --bin "$BIN" \
    --max-steps 1 --jobs 2 --sshlogin : --timeout 600
}

echo "campaign_test: first call"
rc=0; campaign > "$TMP/first.log" 2>&1 || rc=$?
[ "$rc" -eq 0 ] || { cat "$TMP/first.log" >&2; fail "campaign.sh exited $rc"; }
cat "$TMP/first.log"

# runs.csv: 3 rows in spec order; the failure is a row with its error.
python3 - "$OUT" <<'EOF' || fail "runs.csv checks"
import csv, json, os, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(out, "runs.csv"))))
def check(cond, msg):
    if not cond:
        print("FAIL:", msg, file=sys.stderr)
        sys.exit(1)
check(len(rows) == 3, "runs.csv has %d data rows, not 3" % len(rows))
check([r["strategy"] for r in rows] == ["nbv", "nearest", "nbv"], "rows not in spec order")
for r in rows[:2]:
    check(r["exit_status"] == "0" and r["error"] == "", "run %s failed: %s" % (r["run_dir"], r["error"]))
    check(r["termination_reason"] == "max_steps", "%s: termination %s" % (r["run_dir"], r["termination_reason"]))
    check(r["steps"] == "1", "%s: %s steps, not 1" % (r["run_dir"], r["steps"]))
    for k in ("coverage_2d", "path_length_m", "wall_s", "cpu_s", "peak_rss_mb"):
        check(r.get(k, "") != "" and float(r[k]) >= 0, "%s: no %s" % (r["run_dir"], k))
    check(0 < float(r["coverage_2d"]) <= 1, "%s: coverage_2d %s" % (r["run_dir"], r["coverage_2d"]))
    run = json.load(open(os.path.join(out, r["run_dir"], "run.json")))
    check("--max-steps 1" in run["command"], "run.json command: %s" % run["command"])
bad = rows[2]
check(bad["world"] == "no_such_dir/no_such_world.world", "failed row world %s" % bad["world"])
check(bad["exit_status"] not in ("", "0"), "failed row exit status '%s'" % bad["exit_status"])
check(bad["error"].strip() != "", "failed row has no error")
check(bad["coverage_2d"] == "", "failed row has a coverage")
print("campaign_test: runs.csv ok; the failed row says:", bad["error"])
EOF

[ -s "$OUT/report.md" ] || fail "no report.md"
for s in nbv nearest; do
  grep -q "$s" "$OUT/report.md" || fail "report.md does not mention $s"
done
grep -q "no_such_world" "$OUT/report.md" || fail "report.md does not list the failed run"
for png in coverage_vs_path_nbv.png coverage_vs_path_nearest.png path_per_m2_box.png; do
  [ -s "$OUT/$png" ] || fail "no $png"
  head -c 8 "$OUT/$png" | od -An -tx1 | grep -q "89 50 4e 47" || fail "$png is not a PNG"
  grep -q "($png)" "$OUT/report.md" || fail "report.md does not link $png"
done
[ "$(tail -n +2 "$OUT/joblog" | wc -l)" -eq 3 ] || fail "joblog has not 3 jobs after the first call"

# Second call: everything finished, so nothing may run again.
stamp() { for d in "$OUT"/runs/*/; do stat -c '%n %Y %i' "$d/run.json" "$d/stdout.log"; done; }
before=$(stamp)
log_before=$(cat "$OUT/joblog")
sleep 1
echo "campaign_test: second call (must redo nothing)"
rc=0; campaign > "$TMP/second.log" 2>&1 || rc=$?
[ "$rc" -eq 0 ] || { cat "$TMP/second.log" >&2; fail "the second campaign.sh exited $rc"; }
cat "$TMP/second.log"
[ "$(cat "$OUT/joblog")" = "$log_before" ] || fail "the joblog changed: a run was redone"
[ "$(stamp)" = "$before" ] || fail "a run directory changed: a run was redone"
grep -q "\[[0-9]*/3\]" "$TMP/second.log" && fail "the second call ran a job"
[ "$(python3 -c 'import csv,sys; print(len(list(csv.DictReader(open(sys.argv[1])))))' "$OUT/runs.csv")" -eq 3 ] \
  || fail "runs.csv lost rows on the second call"

# scripts/campaign_compare.py: the campaign against a copy with one ATE
# doubled pairs every run, counts that one as worse and lists the failure.
python3 - "$OUT/runs.csv" "$TMP/runs_worse.csv" <<'EOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
rows[0]["ate_rmse_m"] = str(2 * float(rows[0]["ate_rmse_m"]) + 0.01)
w = csv.DictWriter(open(sys.argv[2], "w", newline=""), fieldnames=list(rows[0].keys()))
w.writeheader()
w.writerows(rows)
EOF
"$REPO/scripts/campaign_compare.py" "$OUT" "$TMP/runs_worse.csv" --labels "a,b" --out "$TMP/compare.md" \
  || fail "campaign_compare.py failed"
grep -q "3 paired" "$TMP/compare.md" || fail "compare: not 3 pairs: $(head -5 "$TMP/compare.md")"
grep -q "| ATE RMSE \[m\] | .* | 0 / 1 / 0 |" "$TMP/compare.md" || fail "compare: the doubled ATE is not one worse"
grep -q "no_such_world" "$TMP/compare.md" || fail "compare: the failed run is not listed"
"$REPO/scripts/campaign_compare.py" "$OUT" "$TMP/no_such_runs.csv" > /dev/null 2>&1 \
  && fail "compare: a missing runs.csv is not an error"
# Mission time: every run's simulated time doubled is a ratio of 2 over all
# pairs; joined after the campaign ('+') the doubled runs replace its own.
python3 - "$OUT/runs.csv" "$TMP/runs_slow.csv" <<'EOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for r in rows:
    if r["sim_time_s"]:
        r["sim_time_s"] = str(2 * float(r["sim_time_s"]))
w = csv.DictWriter(open(sys.argv[2], "w", newline=""), fieldnames=list(rows[0].keys()))
w.writeheader()
w.writerows(rows)
EOF
"$REPO/scripts/campaign_compare.py" "$OUT" "$TMP/runs_slow.csv" --out "$TMP/slow.md" || fail "compare (slow) failed"
grep -q "^| all | 2 | [0-9]* -> [0-9]* s: \*\*2.000\*\*" "$TMP/slow.md" \
  || fail "compare: doubled times are not a mission ratio of 2: $(grep -A8 'Mission time' "$TMP/slow.md")"
"$REPO/scripts/campaign_compare.py" "$OUT+$TMP/runs_slow.csv" "$TMP/runs_slow.csv" --out "$TMP/joined.md" \
  || fail "compare (joined) failed"
grep -q "^| all | 2 | [0-9]* -> [0-9]* s: \*\*1.000\*\*" "$TMP/joined.md" \
  || fail "compare: A+B does not replace A's runs by B's: $(grep -A8 'Mission time' "$TMP/joined.md")"

# scripts/check_loops.py: the campaign's runs (dlr_test_room: no loop), then a
# made-up run of 4 stops in a world frame turned 90 deg, whose closure joins
# stop 3 to stop 0: once right, once placed 1 m off (a look-alike room).
"$REPO/scripts/check_loops.py" "$OUT" --out "$TMP/loops.md" || fail "check_loops.py failed on the campaign"
grep -q "0 closure(s), 0 suspect" "$TMP/loops.md" || fail "check_loops: $(head -3 "$TMP/loops.md")"
for v in right false; do
  mkdir -p "$TMP/loops_$v"
  python3 - "$TMP/loops_$v" "$v" <<'EOF'
import math, sys
d, v = sys.argv[1], sys.argv[2]
truth = [(0, 0, 0), (2, 0, 90), (2, 2, 180), (0.1, 2.2, 270)]  # map frame
off = 1.0 if v == "false" else 0.01
with open(d + "/stops.csv", "w") as f:
    f.write("stop,x,y,yaw_deg,loop_closed,loop_with_stop,loop_correction_m,graph_shift_max_m\n")
    for k, (x, y, a) in enumerate(truth):
        if k == 3:
            y -= off
        f.write("%d,%f,%f,%f,%d,%s,0.1,0.1\n" % (k, x, y, a, k == 3, "0" if k == 3 else ""))
with open(d + "/trajectory_gt.tum", "w") as f:  # world = map turned 90 deg, shifted
    for k, (x, y, a) in enumerate(truth):
        wx, wy, wa = 5 - y, 1 + x, math.radians(a + 90)
        f.write("%d %f %f 0 0 0 %f %f\n" % (k, wx, wy, math.sin(wa / 2), math.cos(wa / 2)))
EOF
done
"$REPO/scripts/check_loops.py" "$TMP/loops_right" --fail-on-suspect > "$TMP/right.md" \
  || fail "check_loops: the right closure is suspect: $(cat "$TMP/right.md")"
grep -q "1 closure(s), 0 suspect" "$TMP/right.md" || fail "check_loops: $(cat "$TMP/right.md")"
"$REPO/scripts/check_loops.py" "$TMP/loops_false" --fail-on-suspect > "$TMP/false.md" \
  && fail "check_loops: the false closure passed: $(cat "$TMP/false.md")"
grep -q "1 closure(s), 1 suspect" "$TMP/false.md" || fail "check_loops: $(cat "$TMP/false.md")"
"$REPO/scripts/check_loops.py" "$TMP/no_such_dir" > /dev/null 2>&1 && fail "check_loops: a missing directory is not an error"

# Doors passed (campaign_report.doors_passed): two rooms joined by a 0.85 m
# door and a corridor joined by a 0.95 m one; the truth goes from room 1 into
# room 2 only.
python3 - "$REPO/scripts" "$TMP" <<'EOF' || fail "doors_passed"
import os, sys
sys.dont_write_bytecode = True
sys.path.insert(0, sys.argv[1])
import campaign_report as cr
tmp = sys.argv[2]
building = {"regions": [{"id": 1, "rects": [[0, 0, 4, 4]]}, {"id": 2, "rects": [[4.1, 0, 8, 4]]},
                        {"id": 3, "rects": [[0, 4.1, 8, 6]]}],
            "doors": [{"regions": [1, 2], "width_m": 0.85}, {"regions": [1, 3], "width_m": 0.95}]}
gt = os.path.join(tmp, "doors_gt.tum")
with open(gt, "w") as f:
    f.write("# timestamp tx ty tz qx qy qz qw\n")
    for k, x in enumerate([1.0, 3.0, 5.0, 7.0]):
        f.write("%d %f 2.0 0 0 0 0 1\n" % (k, x))
d = cr.doors_passed(building, gt)
assert d == {"doors": 2, "doors_passed": 1, "doors_narrow": 1, "doors_narrow_passed": 1}, d
assert cr.doors_passed({}, gt)["doors"] is None
assert cr.doors_passed(building, os.path.join(tmp, "missing.tum"))["doors"] is None
print("campaign_test: doors_passed ok")
EOF

ok=1
echo "campaign_test: PASS"
