#!/usr/bin/env bash
# scripts/fingerprint.sh: the same binaries on the same machine print the
# same fingerprints twice (a run is a function of its seed and config), and
# a missing binary is named.
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
BIN=$1
a=$("$REPO/scripts/fingerprint.sh" --bin "$BIN" --steps 5)
b=$("$REPO/scripts/fingerprint.sh" --bin "$BIN" --steps 5)
echo "$a"
grep -q "rawlog md5 [0-9a-f]\{32\}" <<<"$a"
grep -q "rawlog: trajectory md5 [0-9a-f]\{32\}, map.bt md5 [0-9a-f]\{32\}" <<<"$a"
grep -q "5 steps: [0-9]* stops, path [0-9.]* m, trajectory md5 [0-9a-f]\{32\}" <<<"$a"
[ "$a" = "$b" ] || { echo "second run differs:"; echo "$b"; exit 1; }
if "$REPO/scripts/fingerprint.sh" --bin /nonexistent 2> /tmp/fp_err.$$; then
  echo "a missing --bin was accepted"; exit 1
fi
grep -q "/nonexistent/mrpt-sim not found" /tmp/fp_err.$$
rm -f /tmp/fp_err.$$
