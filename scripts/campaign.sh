#!/usr/bin/env bash
# Runs a campaign: a grid of voxplore-explore runs through GNU parallel, then
# the aggregate report (scripts/campaign_report.py).
set -euo pipefail

REPO=$(cd "$(dirname "$0")/.." && pwd)

usage() {
  cat <<'EOF'
Usage: scripts/campaign.sh --spec FILE --out DIR [--jobs N] [--sshlogin LIST | --sshloginfile FILE]
                           [--max-steps N] [--timeout SECONDS] [--config INI] [--bin DIR]
                           [--retry-failed] [--parallel-opts "OPTIONS"]

Runs every line of the spec through voxplore-explore with GNU parallel (Debian
package 'parallel'), one output directory per run, then writes DIR/runs.csv,
DIR/report.md and the plots (scripts/campaign_report.py DIR).

Spec: one run per line, whitespace separated,
    WORLD ROBOT STRATEGY SEED [extra voxplore-explore arguments]
e.g.
    worlds/b7/building.world  compact  nbv      1
    ../shared/worlds/willowgarage/willowgarage_flat_collision.obj compact nearest 1 --start -10,5,0
'#' starts a comment, blank lines are ignored; extra arguments are split at
whitespace (no quoting). WORLD is any file voxplore-explore accepts; a relative
path is resolved against the spec file's folder first, then the repository root
(a world found in neither stays a run, which fails with voxplore-explore's
error). --world, --robot, --strategy, --seed, --out and --config cannot be extra
arguments (they are the spec's columns and the campaign's options); a
--max-steps among them wins over the campaign's. scripts/campaign_spec.sh
writes a spec for N generated buildings.

Options:
  --spec FILE          the spec (required)
  --out DIR            the campaign directory (required); created if missing
  --jobs N             parallel runs per machine (parallel -j: N, or e.g. 50%);
                       default: all local cores (nproc); with --sshlogin/--sshloginfile
                       parallel's default, every core of each machine, unless N is given
                       (or per machine in the login list, e.g. '8/host1,4/host2')
  --sshlogin LIST      passed to parallel --sshlogin: comma separated [N/][user@]host,
                       ':' is this machine (e.g. ':,node1,node2')
  --sshloginfile FILE  passed to parallel --sshloginfile (one sshlogin per line)
  --max-steps N        passed to every run (voxplore-explore --max-steps)
  --timeout SECONDS    wall limit per run (default 3600); a run over it gets
                       SIGTERM (it still writes its outputs), SIGKILL 60 s later, and
                       is a failed run with error "timeout after N s"
  --config INI         voxplore-explore config (default REPO/config/explore.ini)
  --bin DIR            where voxplore-explore is (default REPO/build/bin)
  --retry-failed       also re-run the runs that failed before (parallel --resume-failed)
  --parallel-opts STR  more GNU parallel options, split at whitespace (see below)
  -h, --help           this text

Output (DIR):
  runs/<name>/         one per spec line, <name> = <world>_<robot>_<strategy>_s<seed>
                       [_<hash of the extra arguments>], <world> the world file's stem
                       (its folder's name for a generated .../b<seed>/building.world).
                       Holds voxplore-explore's outputs (summary.json, coverage.csv, ...),
                       stdout.log, stderr.log, time.txt (/usr/bin/time -v) and run.json
                       (spec line, exact command, exit status, wall s, cpu s, peak RSS MB,
                       error). run.json is written last: a run dir without it is unfinished.
  jobs.tsv             the resolved spec, one job per line (parallel's input)
  joblog               parallel's --joblog
  invocations.tsv      start, end, wall s, jobs, sshlogins of every campaign.sh call
                       (the report adds them up to the campaign's wall time)
  runs.csv, report.md, *.png   the aggregate (scripts/campaign_report.py)

Stopping and continuing: stop a campaign with Ctrl-C or 'kill PID' (SIGTERM;
not kill -9, which leaves the runs going). The runs under way are stopped and
left unfinished. Run the same command again and it continues: parallel's
--joblog/--resume skips every run that finished, successful or failed, and
redoes the unfinished ones (campaign.sh drops joblog lines whose run has no
run.json). A run that FAILED (non-zero exit, crash, timeout) is NOT retried
unless --retry-failed is given (parallel --resume-failed). Runs may be appended
to the spec of a campaign under way; changing or removing lines is refused
(the joblog knows runs by their line number): use a new --out DIR, or delete
DIR/joblog (finished runs, those with a run.json, are still not redone).
To redo one run, delete its DIR/runs/<name> and its line in DIR/joblog.

Exit status: 0 every run was run (failed runs are in runs.csv and report.md
with their error); 1 usage or setup error; 130 stopped (SIGINT/SIGTERM).

Other machines (--sshlogin / --sshloginfile): parallel starts each run over ssh
(passwordless keys needed) as
    REPO/scripts/campaign_run.sh --bin BIN --config INI ... --rundir DIR/runs/<name> --world WORLD ...
with these absolute paths, so every machine needs voxplore built at the same
path (REPO, BIN), the worlds at the same paths, perl (parallel runs a small
perl wrapper there), /usr/bin/time (Debian package 'time') and timeout.
  - Shared file system (e.g. /work NFS-mounted everywhere): nothing else is
    needed; the runs write their directories into DIR directly.
  - No shared file system: copy the worlds to every machine beforehand (or let
    parallel copy each run's world file: --parallel-opts "--transferfile {4}";
    only the file itself, so not for .world files that load meshes beside them),
    and have parallel bring each run directory back and clean up:
      --parallel-opts "--return {3} --cleanup"
    ({3} is the run dir, {4} the world in DIR/jobs.tsv). The report then reads
    the returned directories as usual.
  Test it locally: --sshlogin : runs through the same code path on this machine.

Examples:
  scripts/campaign_spec.sh --buildings 20 --worlds-dir out/buildings --with-extra-worlds \
      --out out/campaign.spec
  scripts/campaign.sh --spec out/campaign.spec --out out/campaign --jobs 2
  scripts/campaign.sh --spec out/campaign.spec --out out/campaign --sshlogin ':,node1,node2'
EOF
}

die() { echo "campaign.sh: $*" >&2; exit 1; }

SPEC="" OUT="" JOBS="" SSHLOGIN="" SSHLOGINFILE="" MAX_STEPS="" TIMEOUT=3600
CONFIG="$REPO/config/explore.ini" BIN="$REPO/build/bin" RETRY_FAILED=0 PARALLEL_OPTS=""
while [ $# -gt 0 ]; do
  case "$1" in
    --spec) SPEC=${2:?--spec needs a file}; shift 2 ;;
    --out) OUT=${2:?--out needs a dir}; shift 2 ;;
    --jobs|-j) JOBS=${2:?--jobs needs a number}; shift 2 ;;
    --sshlogin|-S) SSHLOGIN=${2:?--sshlogin needs a list}; shift 2 ;;
    --sshloginfile) SSHLOGINFILE=${2:?--sshloginfile needs a file}; shift 2 ;;
    --max-steps) MAX_STEPS=${2:?--max-steps needs a number}; shift 2 ;;
    --timeout) TIMEOUT=${2:?--timeout needs seconds}; shift 2 ;;
    --config) CONFIG=${2:?--config needs a file}; shift 2 ;;
    --bin) BIN=${2:?--bin needs a dir}; shift 2 ;;
    --retry-failed) RETRY_FAILED=1; shift ;;
    --parallel-opts) PARALLEL_OPTS=${2?--parallel-opts needs options}; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "campaign.sh: unknown argument '$1' (see --help)" >&2; exit 1 ;;
  esac
done
[ -n "$SPEC" ] || die "--spec FILE is required (see --help)"
[ -n "$OUT" ] || die "--out DIR is required (see --help)"
[ -f "$SPEC" ] || die "no spec file '$SPEC'"
[ -z "$SSHLOGIN" ] || [ -z "$SSHLOGINFILE" ] || die "give --sshlogin or --sshloginfile, not both"
[ -z "$SSHLOGINFILE" ] || [ -f "$SSHLOGINFILE" ] || die "no sshlogin file '$SSHLOGINFILE'"
if ! [[ "$TIMEOUT" =~ ^[0-9]+$ ]] || [ "$TIMEOUT" -eq 0 ]; then die "--timeout must be a positive number of seconds"; fi
[ -z "$MAX_STEPS" ] || [[ "$MAX_STEPS" =~ ^[0-9]+$ ]] || die "--max-steps must be a number"
[ -z "$JOBS" ] || [[ "$JOBS" =~ ^[0-9]+%?$ ]] || die "--jobs must be a number (or N%)"
command -v parallel >/dev/null || die "GNU parallel is missing (Debian package 'parallel'; scripts/install_deps.sh installs it)"
[ -x /usr/bin/time ] || die "/usr/bin/time is missing (Debian package 'time')"
command -v python3 >/dev/null || die "python3 is missing"
abspath() { realpath -m -- "$1"; }
SPEC=$(abspath "$SPEC"); OUT=$(abspath "$OUT"); CONFIG=$(abspath "$CONFIG"); BIN=$(abspath "$BIN")
[ -f "$CONFIG" ] || die "no config '$CONFIG'"
[ -x "$BIN/voxplore-explore" ] || die "no voxplore-explore in '$BIN' (build first: scripts/build.sh, or --bin DIR)"
[ -z "$SSHLOGINFILE" ] || SSHLOGINFILE=$(abspath "$SSHLOGINFILE")
SPEC_DIR=$(dirname "$SPEC")
RUNNER="$REPO/scripts/campaign_run.sh"

# --- the spec -> DIR/jobs.tsv ------------------------------------------------
# jobs.tsv columns (tab separated, no header): 1 job number, 2 run name,
# 3 run dir, 4 world (absolute), 5 robot, 6 strategy, 7 seed, 8 extra
# arguments (single spaces), 9 the world as written in the spec, 10 the spec
# line (comment stripped, whitespace squeezed). campaign_report.py reads it.
mkdir -p "$OUT/runs"
# One campaign.sh at a time per campaign directory.
exec 9>"$OUT/.lock"
flock -n 9 || die "another campaign.sh is running on $OUT"
tmp_jobs=$(mktemp "$OUT/.jobs.XXXXXX")
trap 'rm -f "$tmp_jobs"' EXIT
declare -A seen=()
n=0 lineno=0
while IFS= read -r raw || [ -n "$raw" ]; do
  lineno=$((lineno + 1))
  line=${raw%%#*}
  read -r -a f <<< "$line" || true
  [ ${#f[@]} -eq 0 ] && continue
  [ ${#f[@]} -ge 4 ] || die "$SPEC:$lineno: need 'WORLD ROBOT STRATEGY SEED [args]', got '$line'"
  world_in=${f[0]} robot=${f[1]} strategy=${f[2]} seed=${f[3]}
  extra_a=("${f[@]:4}")
  extra="${extra_a[*]}"
  [[ "$seed" =~ ^[0-9]+$ ]] || die "$SPEC:$lineno: seed '$seed' is not a number"
  [[ "$robot" =~ ^[A-Za-z0-9_.-]+$ ]] || die "$SPEC:$lineno: bad robot '$robot'"
  [[ "$strategy" =~ ^[A-Za-z0-9_.-]+$ ]] || die "$SPEC:$lineno: bad strategy '$strategy'"
  for a in "${extra_a[@]}"; do
    case "$a" in
      --world|--world=*|--robot|--robot=*|--strategy|--strategy=*|--seed|--seed=*|--out|--out=*|--config|--config=*|-c|-w|-r|-s|-o)
        die "$SPEC:$lineno: '$a' cannot be an extra argument (it is a spec column or a campaign option)" ;;
    esac
  done
  if [[ "$world_in" = /* ]]; then
    world=$world_in
  elif [ -e "$SPEC_DIR/$world_in" ]; then
    world=$(abspath "$SPEC_DIR/$world_in")
  elif [ -e "$REPO/$world_in" ]; then
    world=$(abspath "$REPO/$world_in")
  else
    world=$(abspath "$SPEC_DIR/$world_in")
  fi
  [ -e "$world" ] || echo "campaign.sh: warning: $SPEC:$lineno: no world file '$world_in' (looked in $SPEC_DIR and $REPO); the run will fail" >&2
  wfile=$(basename "$world")
  stem=${wfile%.*}
  [ "$stem" = building ] && stem=$(basename "$(dirname "$world")")
  name="${stem}_${robot}_${strategy}_s${seed}"
  [ -z "$extra" ] || name+="_$(printf '%s' "$extra" | sha1sum | cut -c1-7)"
  name=$(printf '%s' "$name" | tr -c 'A-Za-z0-9._-' '_')
  if [ -n "${seen[$name]:-}" ]; then
    die "$SPEC:$lineno: same run name '$name' as line ${seen[$name]} (a repeated line, or two worlds with one name: rename one)"
  fi
  seen[$name]=$lineno
  n=$((n + 1))
  printf '%d\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$n" "$name" "$OUT/runs/$name" "$world" \
    "$robot" "$strategy" "$seed" "$extra" "$world_in" "${f[*]}" >> "$tmp_jobs"
done < "$SPEC"

# A continued campaign must have the same jobs under the same numbers (new
# lines at the end are fine): parallel's joblog knows them by number.
if [ -f "$OUT/joblog" ] && [ -f "$OUT/jobs.tsv" ]; then
  old_n=$(wc -l < "$OUT/jobs.tsv")
  if ! head -n "$old_n" "$tmp_jobs" | cmp -s - "$OUT/jobs.tsv"; then
    die "the spec differs from the one this campaign was started with ($OUT/jobs.tsv) in other ways than new lines at the end; use a new --out DIR, or delete $OUT/joblog to continue anyway (finished runs are still not redone)"
  fi
fi
mv -f "$tmp_jobs" "$OUT/jobs.tsv"
trap - EXIT
cp -f "$SPEC" "$OUT/spec.txt" 2>/dev/null || true

# --- reconcile the joblog with the run dirs ----------------------------------
# parallel logs a job whose wrapper exited (also an interrupted one, exit 130)
# and --resume would skip it: keep only the lines of runs that finished
# (run.json present), so the unfinished ones are redone.
if [ -f "$OUT/joblog" ]; then
  awk -F'\t' -v runs="$OUT/jobs.tsv" '
    BEGIN { while ((getline l < runs) > 0) { split(l, c, "\t"); dir[c[1]] = c[3] } }
    NR == 1 { print; next }
    { d = dir[$1]; if (d != "" && (getline x < (d "/run.json")) > 0) { close(d "/run.json"); print } }
  ' "$OUT/joblog" > "$OUT/joblog.tmp"
  dropped=$(( $(wc -l < "$OUT/joblog") - $(wc -l < "$OUT/joblog.tmp") ))
  mv -f "$OUT/joblog.tmp" "$OUT/joblog"
  [ "$dropped" -eq 0 ] || echo "campaign.sh: $dropped unfinished run(s) of an earlier call will be redone" >&2
fi

done_before=0 log_lines=0
if [ -f "$OUT/joblog" ]; then
  done_before=$(awk -F'\t' 'NR > 1 { s[$1] = 1 } END { print length(s) }' "$OUT/joblog")
  log_lines=$(wc -l < "$OUT/joblog")
fi
echo "campaign.sh: $n run(s) in $SPEC, $done_before finished before; outputs in $OUT" >&2

# --- parallel ----------------------------------------------------------------
popts=(--will-cite --colsep '\t' --joblog "$OUT/joblog")
if [ "$RETRY_FAILED" -eq 1 ]; then popts+=(--resume-failed); else popts+=(--resume); fi
if [ -n "$JOBS" ]; then
  popts+=(--jobs "$JOBS")
elif [ -z "$SSHLOGIN" ] && [ -z "$SSHLOGINFILE" ]; then
  popts+=(--jobs "$(nproc)")
fi
[ -z "$SSHLOGIN" ] || popts+=(--sshlogin "$SSHLOGIN")
[ -z "$SSHLOGINFILE" ] || popts+=(--sshloginfile "$SSHLOGINFILE")
# Progress: a bar on a terminal; otherwise each run prints one line when done.
[ -t 2 ] && popts+=(--bar)
if [ -n "$PARALLEL_OPTS" ]; then read -r -a extra_popts <<< "$PARALLEL_OPTS"; popts+=("${extra_popts[@]}"); fi
ropts=(--bin "$BIN" --config "$CONFIG" --timeout "$TIMEOUT")
[ -z "$MAX_STEPS" ] || ropts+=(--max-steps "$MAX_STEPS")
[ "$RETRY_FAILED" -eq 0 ] || ropts+=(--retry-failed)

start=$(date +%s.%N)
stopped=0
rc=0
if [ "$n" -gt 0 ]; then
  parallel "${popts[@]}" "$RUNNER" "${ropts[@]}" --job "{1}/$n" --rundir '{3}' --world '{4}' \
    --robot '{5}' --strategy '{6}' --seed '{7}' --extra '{8}' --line '{10}' :::: "$OUT/jobs.tsv" &
  ppid=$!
  # parallel runs in the background so that a SIGTERM to this script is
  # handled at once: parallel then stops the runs under way (they are logged
  # as unfinished and redone next time).
  trap 'stopped=1; kill -TERM "$ppid" 2>/dev/null || true' INT TERM HUP
  while :; do
    rc=0; wait "$ppid" || rc=$?
    kill -0 "$ppid" 2>/dev/null || break
  done
  trap - INT TERM HUP
fi
end=$(date +%s.%N)
ran=0
if [ -f "$OUT/joblog" ]; then ran=$(( $(wc -l < "$OUT/joblog") - log_lines - (log_lines == 0 ? 1 : 0) )); fi
[ -f "$OUT/invocations.tsv" ] || printf 'start\tend\twall_s\tjobs\tsshlogin\tjobs_run\tstatus\n' > "$OUT/invocations.tsv"
printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$start" "$end" "$(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.1f", b-a}')" \
  "${JOBS:-$( [ -z "$SSHLOGIN$SSHLOGINFILE" ] && nproc || echo default)}" "${SSHLOGIN:-${SSHLOGINFILE:-local}}" \
  "$ran" "$( [ "$stopped" -eq 1 ] && echo stopped || echo "parallel exit $rc")" >> "$OUT/invocations.tsv"

if [ "$stopped" -eq 1 ]; then
  echo "campaign.sh: stopped; run the same command again to continue ($OUT)" >&2
  exit 130
fi
# parallel: 0 all ok, 1-101 that many runs failed (recorded in their run.json),
# 255 something else went wrong (e.g. an ssh login).
if [ "$rc" -ge 102 ]; then
  echo "campaign.sh: GNU parallel failed (exit $rc); runs without a run.json are redone next time" >&2
fi
nfailed=0 nunfinished=0
while IFS=$'\t' read -r _ _ rdir _; do
  if [ ! -f "$rdir/run.json" ]; then nunfinished=$((nunfinished + 1))
  elif ! grep -q '"error": null' "$rdir/run.json"; then nfailed=$((nfailed + 1)); fi
done < "$OUT/jobs.tsv"
echo "campaign.sh: $n run(s): $((n - nfailed - nunfinished)) ok, $nfailed failed, $nunfinished unfinished; this call ran $ran job(s) in $(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.0f", b-a}') s" >&2

python3 "$REPO/scripts/campaign_report.py" "$OUT"
[ "$rc" -lt 102 ] || exit 1
[ "$nunfinished" -eq 0 ] || { echo "campaign.sh: $nunfinished run(s) unfinished; run the same command again" >&2; exit 1; }
exit 0
