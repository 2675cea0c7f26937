#!/usr/bin/env bash
# One run of a campaign (called by scripts/campaign.sh through GNU parallel,
# locally or on an --sshlogin host; everything it needs comes in as arguments,
# so it needs no file of the campaign besides the world and the binaries).
#
#   campaign_run.sh --bin DIR --config INI --timeout S [--max-steps N] [--retry-failed]
#                   --job I/TOTAL --rundir DIR --world FILE --robot R --strategy S
#                   --seed N --extra "ARGS" --line "SPEC LINE"
#
# Runs voxplore-explore under /usr/bin/time -v (peak RSS, CPU user + sys) and
# timeout (wall limit; SIGTERM, which voxplore-explore answers by writing every
# output, then SIGKILL 60 s later), with --out RUNDIR, and writes
#   RUNDIR/stdout.log, RUNDIR/stderr.log, RUNDIR/time.txt (time -v's report),
#   RUNDIR/run.json: the spec line, the exact command, host and CPU model (a
#     run's course can differ from machine to machine: BENCHMARKS.md), exit
#     status, wall s, cpu s, peak RSS MB, and error (null on success; the last stderr line, or
#     "timeout after N s", on failure).
# run.json is written last (atomically): a run dir without it is unfinished.
#
# Exit status: 0 the run succeeded (exit 0 and summary.json written); 1 the
# run failed and the failure is recorded in run.json (parallel carries on with
# the other runs either way, and its joblog shows the failure, which is what
# campaign.sh --retry-failed / parallel --resume-failed retries); 130 the run
# was interrupted (the wrapper or voxplore-explore got SIGINT/SIGTERM because
# the campaign was stopped): no run.json, the run is redone when the campaign
# is continued. A finished run (run.json present) is not redone: exits with
# its recorded result at once, unless --retry-failed and it failed.
set -euo pipefail

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; }

BIN="" CONFIG="" TIMEOUT=3600 MAX_STEPS="" RETRY_FAILED=0 JOB="" RUNDIR="" WORLD="" ROBOT=""
STRATEGY="" SEED="" EXTRA="" LINE=""
while [ $# -gt 0 ]; do
  case "$1" in
    --bin) BIN=$2; shift 2 ;;
    --config) CONFIG=$2; shift 2 ;;
    --timeout) TIMEOUT=$2; shift 2 ;;
    --max-steps) MAX_STEPS=$2; shift 2 ;;
    --retry-failed) RETRY_FAILED=1; shift ;;
    --job) JOB=$2; shift 2 ;;
    --rundir) RUNDIR=$2; shift 2 ;;
    --world) WORLD=$2; shift 2 ;;
    --robot) ROBOT=$2; shift 2 ;;
    --strategy) STRATEGY=$2; shift 2 ;;
    --seed) SEED=$2; shift 2 ;;
    --extra) EXTRA=$2; shift 2 ;;
    --line) LINE=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "campaign_run.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
for v in BIN CONFIG RUNDIR WORLD ROBOT STRATEGY SEED; do
  [ -n "${!v}" ] || { echo "campaign_run.sh: missing --${v,,}" >&2; exit 2; }
done
[[ "$SEED" =~ ^[0-9]+$ ]] || { echo "campaign_run.sh: --seed must be a number" >&2; exit 2; }
case "$RUNDIR" in
  */runs/?*) ;;
  *) echo "campaign_run.sh: refusing run dir '$RUNDIR' (must be .../runs/NAME)" >&2; exit 2 ;;
esac
NAME=$(basename "$RUNDIR")
TAG="[${JOB:-?}] $NAME"

# JSON string (control characters escaped or dropped).
json_str() {
  local s=$1
  s=${s//\\/\\\\}; s=${s//\"/\\\"}; s=${s//$'\t'/\\t}; s=${s//$'\n'/\\n}; s=${s//$'\r'/\\r}
  s=$(printf '%s' "$s" | tr -d '\000-\010\013\014\016-\037')
  printf '"%s"' "$s"
}
json_num() { if [ -n "$1" ]; then printf '%s' "$1"; else printf 'null'; fi; }

# --- a finished run is not redone ------------------------------------------
if [ -f "$RUNDIR/run.json" ]; then
  if grep -q '"error": null' "$RUNDIR/run.json"; then
    echo "$TAG: already done"; exit 0
  fi
  if [ "$RETRY_FAILED" -eq 0 ]; then
    echo "$TAG: failed before, not retried (campaign.sh --retry-failed retries it)"; exit 1
  fi
  echo "$TAG: retrying the failed run"
fi
# An unfinished (interrupted) or retried run starts from an empty dir.
rm -rf -- "$RUNDIR"
mkdir -p -- "$RUNDIR"

# --- the command -------------------------------------------------------------
cmd=("$BIN/voxplore-explore" --config "$CONFIG" --world "$WORLD" --robot "$ROBOT"
     --strategy "$STRATEGY" --seed "$SEED" --out "$RUNDIR")
read -r -a extra <<< "$EXTRA" || true
has_max_steps=0
for a in "${extra[@]}"; do
  case "$a" in -n|--max-steps|--max-steps=*) has_max_steps=1 ;; esac
done
# The spec line's own --max-steps wins over the campaign's.
if [ -n "$MAX_STEPS" ] && [ "$has_max_steps" -eq 0 ]; then cmd+=(--max-steps "$MAX_STEPS"); fi
cmd+=("${extra[@]}")
printf -v cmd_str '%q ' "${cmd[@]}"
cmd_str=${cmd_str% }

# --- run it ------------------------------------------------------------------
interrupted=0
child=""
# shellcheck disable=SC2317  # called by the trap
on_signal() {
  interrupted=1
  # time -> timeout (its own process group) -> voxplore-explore: signal the
  # timeout's group so voxplore-explore gets it, then time.
  if [ -n "$child" ]; then
    local t
    for t in $(ps -o pid= --ppid "$child" 2>/dev/null); do kill -TERM -- "-$t" 2>/dev/null || true; done
    kill -TERM "$child" 2>/dev/null || true
  fi
}
trap on_signal INT TERM HUP

started=$(date -u +%Y-%m-%dT%H:%M:%SZ)
t0=$(date +%s.%N)
set +e
/usr/bin/time -v -o "$RUNDIR/time.txt" \
  timeout --kill-after=60 "$TIMEOUT" "${cmd[@]}" >"$RUNDIR/stdout.log" 2>"$RUNDIR/stderr.log" &
child=$!
status=0
while :; do
  wait "$child"; status=$?
  # wait returns early (> 128) when a trapped signal arrives; wait again
  # until the child has really exited.
  kill -0 "$child" 2>/dev/null || break
done
set -e
t1=$(date +%s.%N)
trap - INT TERM HUP

# voxplore-explore exits 130 when it got SIGINT/SIGTERM (someone stopped the
# campaign, not the run's fault): leave the run unfinished so it is redone.
if [ "$interrupted" -eq 1 ] || [ "$status" -eq 130 ] || [ "$status" -eq 143 ]; then
  echo "$TAG: interrupted (exit $status), redone when the campaign continues"
  exit 130
fi

wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f", b-a}')
user="" sys="" rss_kb="" cpu="" rss_mb=""
if [ -f "$RUNDIR/time.txt" ]; then
  user=$(sed -n 's/^[[:space:]]*User time (seconds): *//p' "$RUNDIR/time.txt" | tail -1)
  sys=$(sed -n 's/^[[:space:]]*System time (seconds): *//p' "$RUNDIR/time.txt" | tail -1)
  rss_kb=$(sed -n 's/^[[:space:]]*Maximum resident set size (kbytes): *//p' "$RUNDIR/time.txt" | tail -1)
fi
[ -n "$user" ] && [ -n "$sys" ] && cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN{printf "%.2f", u+s}')
[ -n "$rss_kb" ] && rss_mb=$(awk -v k="$rss_kb" 'BEGIN{printf "%.1f", k/1024}')

# timeout exits 124 when the limit hit, 137 when voxplore-explore then
# needed the SIGKILL of --kill-after (an OOM kill also gives 137: tell them
# apart by the wall time).
timed_out=0
if [ "$status" -eq 124 ]; then timed_out=1; fi
if [ "$status" -eq 137 ] && awk -v w="$wall" -v t="$TIMEOUT" 'BEGIN{exit !(w >= t)}'; then timed_out=1; fi
error=""
if [ "$timed_out" -eq 1 ]; then
  error="timeout after $TIMEOUT s"
elif [ "$status" -ne 0 ]; then
  error=$(grep -v '^[[:space:]]*$' "$RUNDIR/stderr.log" 2>/dev/null | tail -1 || true)
  if [ -z "$error" ]; then
    sig=$(sed -n 's/^Command terminated by signal \([0-9]*\).*/\1/p' "$RUNDIR/time.txt" 2>/dev/null | tail -1)
    if [ -n "$sig" ]; then error="killed by signal $sig"; else error="exit status $status"; fi
  fi
elif [ ! -s "$RUNDIR/summary.json" ]; then
  error="exit status 0 but no summary.json"
  status=1
fi

argv_json="["
for a in "${cmd[@]}"; do argv_json+="$(json_str "$a"), "; done
argv_json="${argv_json%, }]"

tmp="$RUNDIR/run.json.tmp"
{
  printf '{\n'
  printf '  "name": %s,\n' "$(json_str "$NAME")"
  printf '  "job": %s,\n' "$(json_str "$JOB")"
  printf '  "spec_line": %s,\n' "$(json_str "$LINE")"
  printf '  "world": %s,\n' "$(json_str "$WORLD")"
  printf '  "robot": %s,\n' "$(json_str "$ROBOT")"
  printf '  "strategy": %s,\n' "$(json_str "$STRATEGY")"
  printf '  "seed": %s,\n' "$SEED"
  printf '  "extra_args": %s,\n' "$(json_str "$EXTRA")"
  printf '  "command": %s,\n' "$(json_str "$cmd_str")"
  printf '  "argv": %s,\n' "$argv_json"
  printf '  "host": %s,\n' "$(json_str "$(hostname)")"
  printf '  "cpu": %s,\n' "$(json_str "$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -n 1)")"
  printf '  "started": %s,\n' "$(json_str "$started")"
  printf '  "timeout_s": %s,\n' "$(json_num "$TIMEOUT")"
  printf '  "exit_status": %s,\n' "$status"
  printf '  "wall_s": %s,\n' "$(json_num "$wall")"
  printf '  "user_s": %s,\n' "$(json_num "$user")"
  printf '  "sys_s": %s,\n' "$(json_num "$sys")"
  printf '  "cpu_s": %s,\n' "$(json_num "$cpu")"
  printf '  "peak_rss_mb": %s,\n' "$(json_num "$rss_mb")"
  if [ -n "$error" ]; then printf '  "error": %s\n' "$(json_str "$error")"; else printf '  "error": null\n'; fi
  printf '}\n'
} > "$tmp"
mv -f -- "$tmp" "$RUNDIR/run.json"

if [ -z "$error" ]; then
  term=$(sed -n 's/^[[:space:]]*"termination_reason": *"\([^"]*\)".*/\1/p' "$RUNDIR/summary.json" | head -1)
  cov=$(sed -n 's/^[[:space:]]*"coverage_2d": *\([^,]*\).*/\1/p' "$RUNDIR/summary.json" | head -1)
  echo "$TAG: ok ($term, coverage_2d $cov, ${wall} s wall, ${cpu:-?} s cpu, ${rss_mb:-?} MB)"
  exit 0
fi
echo "$TAG: FAILED (exit $status: $error)"
exit 1
