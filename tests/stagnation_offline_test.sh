#!/usr/bin/env bash
# scripts/stagnation_offline.py on two made-up coverage.csv traces: one whose
# floor stops growing for longer than the window (the rule ends it at the
# first step the window is driven), one the planner ends first (untouched).
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
{
  echo "step,stops,sim_time_s,path_length_m,coverage_2d,done,known_floor_m2"
  echo "1,1,0,0,0.10,no,10"
  echo "2,5,10,40,0.50,no,50"
  echo "3,9,20,80,0.90,no,90"   # the floor stops growing here
  echo "4,13,30,120,0.91,no,91"
  echo "5,17,40,160,0.91,no,92"
  echo "6,21,50,200,0.92,no,93"  # 120 m driven since step 3, +3 m^2
  echo "7,25,60,240,0.93,no,94"
} > "$T/plateau.csv"
{
  echo "step,stops,sim_time_s,path_length_m,coverage_2d,done,known_floor_m2"
  echo "1,1,0,0,0.10,no,10"
  echo "2,5,10,200,0.95,no,95"
  echo "3,9,20,400,0.96,no frontier,96"
} > "$T/ends.csv"
out=$(python3 "$REPO/scripts/stagnation_offline.py" "$T" --window 120 --gain 5 --runs)
echo "$out"
grep -q "| 120 | 5 | 1 of 2 | 0.010 plateau 0.930 -> 0.920 | 0.920 | 640 -> 600 |" <<<"$out"
grep -q "plateau .*path    240 ->    200  stagnation at step 6" <<<"$out"
grep -q "ends .*path    400 ->    400  no frontier" <<<"$out"
# A window longer than the plateau: nothing ends.
python3 "$REPO/scripts/stagnation_offline.py" "$T" --window 200 --gain 5 | grep -q "| 200 | 5 | 0 of 2 |"
# --guard: no end at a step with a new frontier (a room never targeted).
G=$(mktemp -d); trap 'rm -rf "$T" "$G"' EXIT
{
  echo "step,stops,sim_time_s,path_length_m,coverage_2d,done,known_floor_m2,new_frontiers"
  echo "1,1,0,0,0.10,no,10,3"
  echo "2,5,10,40,0.50,no,50,2"
  echo "3,9,20,80,0.90,no,90,0"
  echo "4,13,30,120,0.91,no,91,0"
  echo "5,17,40,160,0.91,no,92,0"
  echo "6,21,50,200,0.92,no,93,1"  # the window says stop; a new frontier says no
  echo "7,25,60,240,0.93,no,94,0"
} > "$G/guarded.csv"
python3 "$REPO/scripts/stagnation_offline.py" "$G" --window 120 --gain 5 --runs | grep -q "guarded .*stagnation at step 6"
python3 "$REPO/scripts/stagnation_offline.py" "$G" --window 120 --gain 5 --runs --guard | grep -q "guarded .*stagnation at step 7"
# --guard on traces without the column is an error naming the run.
if python3 "$REPO/scripts/stagnation_offline.py" "$T" --guard 2> "$T/err"; then exit 1; fi
grep -q "has no new_frontiers column" "$T/err"
# A campaign of the old format is an error naming the file.
echo "step,path_length_m,coverage_2d" > "$T/old.csv"
if python3 "$REPO/scripts/stagnation_offline.py" "$T" 2> "$T/err"; then exit 1; fi
grep -q "old.csv has no known_floor_m2 column" "$T/err"
echo "stagnation_offline_test: ok"
