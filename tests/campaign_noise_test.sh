#!/usr/bin/env bash
# scripts/campaign_noise.py on made-up runs.csv files: a null campaign whose
# runs move both ways by a few mm / m gives a band; a change that lowers
# every run's coverage by 0.05 lies beyond it, one that moves the path by
# less than the null's spread does not; bad input names the file.
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
H="run_dir,coverage_2d,ate_rmse_m,ate_online_rmse_m,map_precision_above_floor,path_length_m,loop_closures,min_clearance_m"
for f in base null change; do echo "$H" > "$T/$f.csv"; done
for w in 1 2 3 4 5 6; do
  for s in nbv nearest; do
    r="b${w}_compact_${s}_s1"
    sgn=$(( (w % 2) * 2 - 1 ))   # +1 / -1 by world: the null moves both ways
    p=$(( 300 + 10 * w ))
    [ "$s" = nbv ] && p=$(( p - 60 ))
    echo "out/runs/$r,0.975,0.045,0.040,0.95,$p,1,0.03" >> "$T/base.csv"
    echo "out/runs/$r,0.97$(( 5 + sgn * 3 )),0.04$(( 5 + sgn * 2 )),0.040,0.95,$(( p + sgn * 30 )),1,0.03" >> "$T/null.csv"
    echo "out/runs/$r,0.925,0.045,0.040,0.95,$(( p + 5 )),1,0.03" >> "$T/change.csv"
  done
done
out=$(python3 "$REPO/scripts/campaign_noise.py" "$T/base.csv" "$T/null.csv" "$T/change.csv")
echo "$out"
grep -q "^12 runs common to 3 campaigns" <<<"$out"
# null - base of coverage: +-0.003 per run, mean 0, sd 0.0031, band 2 sd / sqrt(12) = 0.0018
grep -qE "^\| coverage_2d \| 0\.975 \| \+0\.0000 \| .* \| 6 / 6 \| 0\.003133 \| \+-0\.00181 \| -0\.0500 \(beyond\) \(-0\.0500, 0 / 12\) \|$" <<<"$out"
# path: the change's +5 m is inside the null's +-30 m spread
grep -qE "^\| path per run \[m\] \| .* \| \+5\.0 \(\+5\.0, 12 / 0\) \|$" <<<"$out"
grep -q "| nbv / nearest path (6 pairs) |" <<<"$out"
# bad input names the file
if python3 "$REPO/scripts/campaign_noise.py" "$T/base.csv" "$T/missing.csv" 2>"$T/err"; then exit 1; fi
grep -q "missing.csv: no such runs.csv or campaign directory" "$T/err"
printf "run_dir_typo,coverage_2d\nb1,0.9\n" > "$T/bad.csv"
if python3 "$REPO/scripts/campaign_noise.py" "$T/base.csv" "$T/bad.csv" 2>"$T/err"; then exit 1; fi
grep -q "bad.csv: no run_dir column" "$T/err"
echo ok
