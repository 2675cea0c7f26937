#!/usr/bin/env bash
# Writes a campaign spec (scripts/campaign.sh) for N generated buildings, and
# generates the buildings that are not there yet.
set -euo pipefail

REPO=$(cd "$(dirname "$0")/.." && pwd)

usage() {
  cat <<'EOF'
Usage: scripts/campaign_spec.sh --buildings N --worlds-dir DIR [--seed0 S] [--robots "omnirob compact"]
                                [--strategies "nbv nearest"] [--run-seed K] [--layout NAME]
                                [--with-extra-worlds] [--worldgen-config INI] [--bin DIR] [--out SPECFILE]

Generates N buildings with voxplore-worldgen --seed S+i --out DIR/b<S+i> (i = 0..N-1;
a building whose DIR/b<seed>/building.world exists is kept, not generated again)
and writes a spec with one line per building x robot x strategy:
    <DIR/b<seed>/building.world> <robot> <strategy> <run seed>

Options:
  --buildings N          number of buildings (required; 0 with --with-extra-worlds
                         writes only the extra worlds)
  --worlds-dir DIR       where the buildings go (required)
  --seed0 S              the first building's seed (default 1)
  --robots LIST          robots, space separated (default "omnirob compact")
  --strategies LIST      strategies, space separated (default "nbv nearest")
  --run-seed K           voxplore-explore --seed of every run (default 1)
  --layout NAME          passed to voxplore-worldgen --layout (corridor|ring|branching|
                         hall|mixed); default: the generator's choice ([worldgen] layout)
  --worldgen-config INI  passed to voxplore-worldgen --config
  --with-extra-worlds    append simulated_worlds/office.world (every robot and strategy),
                         the shared worlds of simulated_worlds/shared_world_starts.txt
                         (every robot and strategy, its start as
                         --start x,y,yaw) and willowgarage (every robot, --start -10,5,0,
                         every strategy). The shared worlds are under ../shared/worlds
                         (relative to the repository); when that is missing they are
                         skipped with a warning.
  --bin DIR              where voxplore-worldgen is (default REPO/build/bin)
  --out SPECFILE         the spec to write (default: standard output); world paths in it
                         are relative to the spec's folder (absolute on standard output)
  -h, --help             this text

Example:
  scripts/campaign_spec.sh --buildings 20 --worlds-dir out/buildings --with-extra-worlds \
      --out out/campaign.spec
  scripts/campaign.sh --spec out/campaign.spec --out out/campaign
EOF
}

die() { echo "campaign_spec.sh: $*" >&2; exit 1; }

N="" WORLDS="" SEED0=1 ROBOTS="omnirob compact" STRATEGIES="nbv nearest" RUN_SEED=1 LAYOUT=""
WG_CONFIG="" EXTRA=0 BIN="$REPO/build/bin" OUTFILE=""
while [ $# -gt 0 ]; do
  case "$1" in
    --buildings) N=${2:?--buildings needs a number}; shift 2 ;;
    --worlds-dir) WORLDS=${2:?--worlds-dir needs a dir}; shift 2 ;;
    --seed0) SEED0=${2:?--seed0 needs a number}; shift 2 ;;
    --robots) ROBOTS=${2:?--robots needs a list}; shift 2 ;;
    --strategies) STRATEGIES=${2:?--strategies needs a list}; shift 2 ;;
    --run-seed) RUN_SEED=${2:?--run-seed needs a number}; shift 2 ;;
    --layout) LAYOUT=${2:?--layout needs a name}; shift 2 ;;
    --worldgen-config) WG_CONFIG=${2:?--worldgen-config needs a file}; shift 2 ;;
    --with-extra-worlds) EXTRA=1; shift ;;
    --bin) BIN=${2:?--bin needs a dir}; shift 2 ;;
    --out) OUTFILE=${2:?--out needs a file}; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "campaign_spec.sh: unknown argument '$1' (see --help)" >&2; exit 1 ;;
  esac
done
[ -n "$N" ] || die "--buildings N is required (see --help)"
[ -n "$WORLDS" ] || die "--worlds-dir DIR is required (see --help)"
[[ "$N" =~ ^[0-9]+$ ]] || die "--buildings must be a number"
[[ "$SEED0" =~ ^[0-9]+$ ]] || die "--seed0 must be a number"
[[ "$RUN_SEED" =~ ^[0-9]+$ ]] || die "--run-seed must be a number"
read -r -a robots <<< "$ROBOTS" || true
read -r -a strategies <<< "$STRATEGIES" || true
[ ${#robots[@]} -gt 0 ] || die "--robots is empty"
[ ${#strategies[@]} -gt 0 ] || die "--strategies is empty"
[ -z "$WG_CONFIG" ] || [ -f "$WG_CONFIG" ] || die "no worldgen config '$WG_CONFIG'"
WORLDS=$(realpath -m -- "$WORLDS")
BIN=$(realpath -m -- "$BIN")
[ -z "$WG_CONFIG" ] || WG_CONFIG=$(realpath -- "$WG_CONFIG")

# Paths in the spec (campaign.sh resolves a relative WORLD against the spec's
# folder first, then the repository root): relative to the spec's folder when
# under it, relative to the repository when under it or beside it (e.g.
# simulated_worlds/office.world, ../shared/worlds/...) and not shadowed by a
# file of that name beside the spec, absolute otherwise and on standard output.
SPEC_DIR=""
if [ -n "$OUTFILE" ]; then
  OUTFILE=$(realpath -m -- "$OUTFILE")
  SPEC_DIR=$(dirname "$OUTFILE")
  mkdir -p "$SPEC_DIR"
fi
REPO_PARENT=$(dirname "$REPO")
spec_path() {
  local abs rel
  abs=$(realpath -m -- "$1")
  if [ -z "$SPEC_DIR" ]; then printf '%s\n' "$abs"; return; fi
  case "$abs" in
    "$SPEC_DIR"/*) realpath -m --relative-to="$SPEC_DIR" -- "$abs"; return ;;
  esac
  case "$abs" in
    "$REPO_PARENT"/*)
      rel=$(realpath -m --relative-to="$REPO" -- "$abs")
      if [ ! -e "$SPEC_DIR/$rel" ]; then printf '%s\n' "$rel"; return; fi ;;
  esac
  printf '%s\n' "$abs"
}

# --- the buildings ---------------------------------------------------------------
lines=()
generated=0 kept=0
if [ "$N" -gt 0 ]; then
  [ -x "$BIN/voxplore-worldgen" ] || die "no voxplore-worldgen in '$BIN' (build first: scripts/build.sh, or --bin DIR)"
  mkdir -p "$WORLDS"
fi
for ((i = 0; i < N; i++)); do
  seed=$((SEED0 + i))
  dir="$WORLDS/b$seed"
  if [ -f "$dir/building.world" ]; then
    kept=$((kept + 1))
    if [ -n "$LAYOUT" ]; then
      have=$(sed -n 's/^[[:space:]]*"layout": *"\([^"]*\)".*/\1/p' "$dir/building.json" 2>/dev/null | head -1)
      [ "$have" = "$LAYOUT" ] || echo "campaign_spec.sh: warning: kept $dir (layout '${have:-?}', not '$LAYOUT'); delete it to generate it again" >&2
    fi
  else
    args=(--seed "$seed" --out "$dir" --quiet)
    [ -z "$WG_CONFIG" ] || args+=(--config "$WG_CONFIG")
    [ -z "$LAYOUT" ] || args+=(--layout "$LAYOUT")
    "$BIN/voxplore-worldgen" "${args[@]}" || die "voxplore-worldgen ${args[*]} failed"
    [ -f "$dir/building.world" ] || die "voxplore-worldgen wrote no $dir/building.world"
    generated=$((generated + 1))
  fi
  w=$(spec_path "$dir/building.world")
  for rb in "${robots[@]}"; do
    for st in "${strategies[@]}"; do lines+=("$w $rb $st $RUN_SEED"); done
  done
done
[ "$N" -eq 0 ] || echo "campaign_spec.sh: $N buildings in $WORLDS ($generated generated, $kept already there)" >&2

# --- the extra worlds ----------------------------------------------------------
if [ "$EXTRA" -eq 1 ]; then
  office="$REPO/simulated_worlds/office.world"
  if [ -f "$office" ]; then
    for rb in "${robots[@]}"; do
      for st in "${strategies[@]}"; do lines+=("$(spec_path "$office") $rb $st $RUN_SEED"); done
    done
  else
    echo "campaign_spec.sh: warning: no $office, skipped" >&2
  fi
  shared="$REPO/../shared/worlds"
  if [ ! -d "$shared" ]; then
    echo "campaign_spec.sh: warning: no shared worlds ($(realpath -m -- "$shared")): the shared worlds and willowgarage are skipped" >&2
  else
    shared=$(realpath -- "$shared")
    starts="$REPO/simulated_worlds/shared_world_starts.txt"
    entries=()
    if [ -f "$starts" ]; then
      while IFS= read -r raw || [ -n "$raw" ]; do
        line=${raw%%#*}
        read -r -a f <<< "$line" || true
        [ ${#f[@]} -eq 0 ] && continue
        [ ${#f[@]} -ge 5 ] || { echo "campaign_spec.sh: warning: $starts: bad line '$raw', skipped" >&2; continue; }
        entries+=("${f[0]} ${f[1]} ${f[2]} ${f[3]} ${f[4]}")
      done < "$starts"
    else
      echo "campaign_spec.sh: warning: no $starts: only willowgarage of the shared worlds" >&2
    fi
    entries+=("willowgarage/willowgarage_flat_collision.obj -10 5 0 compact")
    for e in "${entries[@]}"; do
      read -r rel x y yaw _robot <<< "$e"
      world="$shared/$rel"
      if [ ! -f "$world" ]; then
        echo "campaign_spec.sh: warning: no $world, skipped" >&2
        continue
      fi
      # Every robot: the starts are free for a 2 x 2 m footprint (the line's
      # robot is the one voxplore-bench 'strategies' runs).
      for r in "${robots[@]}"; do
        for st in "${strategies[@]}"; do
          lines+=("$(spec_path "$world") $r $st $RUN_SEED --start $x,$y,$yaw")
        done
      done
    done
  fi
fi

# --- the spec --------------------------------------------------------------------
write_spec() {
  echo "# voxplore campaign spec: WORLD ROBOT STRATEGY SEED [extra voxplore-explore arguments]"
  echo "# written by scripts/campaign_spec.sh --buildings $N --worlds-dir $WORLDS --seed0 $SEED0" \
       "--robots \"$ROBOTS\" --strategies \"$STRATEGIES\" --run-seed $RUN_SEED" \
       "${LAYOUT:+--layout $LAYOUT }${WG_CONFIG:+--worldgen-config $WG_CONFIG }$( [ "$EXTRA" -eq 1 ] && echo --with-extra-worlds)"
  echo "# $(date -u +%Y-%m-%dT%H:%M:%SZ); run it with scripts/campaign.sh --spec THIS --out DIR"
  if [ ${#lines[@]} -gt 0 ]; then printf '%s\n' "${lines[@]}"; fi
}
if [ -n "$OUTFILE" ]; then
  write_spec > "$OUTFILE.tmp"
  mv -f "$OUTFILE.tmp" "$OUTFILE"
  echo "campaign_spec.sh: ${#lines[@]} runs -> $OUTFILE" >&2
else
  write_spec
fi
