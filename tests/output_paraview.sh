#!/usr/bin/env bash
# output_paraview.sh FABRIC SCENE: a small scene on 2 ranks writes DIR/fabric.h5 and DIR/fabric.xmf,
# and ParaView's own XDMF readers (pvpython, tests/check_paraview.py) read the frames, their
# times, the coordinates and the fields that fabric.h5 holds. Twice: frames every load step
# (-output_every 1), and frames every 200 te steps as well (-output_te_every 200: each load step takes
# 171 to 820 te steps here, so that most have te frames; at 1000 none had).
set -u
fabric="$1"; scene="$2"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
opts=(-scene "$scene" -quiet -gauge_mm 20 -width_mm 5 -load_steps 6 -elongation_pct 3 -predict none -point_load_N 0,0,0.001 -balance_tol 1e-4)
fail=0
mpiexec -n 2 "$fabric" "${opts[@]}" -output_every 1 -output_dir "$work/steps" || { echo "FAIL the run failed"; exit 1; }
# frame 0 (rest) and one per load step
pvpython "$here/check_paraview.py" "$work/steps" 7 2>"$work/pv.err" || fail=1
grep -v "DeprecationWarning\|^ *dims\|^$" "$work/pv.err" | head -20

M=200
mpiexec -n 2 "$fabric" "${opts[@]}" -output_every 2 -output_te_every $M -output_dir "$work/te" || { echo "FAIL the run with te frames failed"; exit 1; }
# frame 0, one every M te steps of each load step, and the load-step frames (every 2 and the
# last) that do not fall on a te frame
expected=$(awk -F, -v M=$M -v E=2 -v K=6 'NR > 1 { n += int($5 / M); if (($1 % E == 0 || $1 == K) && $5 % M) n++ } END { print n + 1 }' "$work/te/curve.csv")
echo "te steps per load step: $(cut -d, -f5 "$work/te/curve.csv" | tail -n +2 | tr '\n' ' '), so $expected frames"
pvpython "$here/check_paraview.py" "$work/te" "$expected" te 2>"$work/pv.err" || fail=1
grep -v "DeprecationWarning\|^ *dims\|^$" "$work/pv.err" | head -20
exit $fail
