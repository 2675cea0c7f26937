#!/bin/bash
# rp.sh BIN RUNDIR OUTDIR [extra ini lines] : replay a campaign run with its own SLAM sections
BIN=$1; R=$2; O=$3; shift 3
mkdir -p $O
python3 - "$R/params.ini" "$O/rp.ini" "$@" <<'PY'
import re, sys
s=open(sys.argv[1]).read(); out=[]; keep=False
for line in s.splitlines():
    m=re.match(r'^\[(\w+)\]',line)
    if m: keep = m.group(1) in ('cloud','metaview','icp','octomap','loop_closure')
    if keep: out.append(line)
    if m and m.group(1)=='loop_closure': out.extend(sys.argv[3:])
open(sys.argv[2],'w').write('\n'.join(out)+'\n')
PY
VOXPLORE_LOOP_DEBUG=1 $BIN -q -r $R/run.rawlog -c $O/rp.ini -g $R/trajectory_gt.tum -o $O > $O/replay.out 2> $O/replay.err
cp $R/trajectory_gt.tum $O/ 2>/dev/null
