#!/usr/bin/env bash
# output_ranks.sh FABRIC SCENE: the same scene on 1, 2 and 3 ranks (and 2 x 2) writes fabric.h5
# files whose every dataset and attribute is identical (h5diff), and the same fabric.xmf. Each rank
# writes its own patch through PETSc's HDF5 viewer, so this checks that the patches land where
# they belong and that the point fields do not depend on the split.
set -u
fabric="$1"; scene="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
opts=(-scene "$scene" -quiet -gauge_mm 20 -width_mm 5 -load_steps 4 -elongation_pct 3 -predict none -point_load_N 0,0,0.001
      -balance_tol 1e-4 -output_every 1 -output_te_every 4000)
fail=0
for np in 1 2 3; do
  mpiexec -n $np "$fabric" "${opts[@]}" -output_dir "$work/np$np" >/dev/null || { echo "FAIL the run on $np ranks failed"; fail=1; }
done
mpiexec -n 4 "$fabric" "${opts[@]}" -da_processors_x 2 -da_processors_y 2 -output_dir "$work/np4" >/dev/null || { echo "FAIL the run on 2 x 2 ranks failed"; fail=1; }
frames=$(h5ls "$work/np1/fabric.h5/frames" 2>/dev/null | wc -l)
[[ $frames -ge 5 ]] && echo "PASS 1 rank wrote $frames frames" || { echo "FAIL 1 rank wrote $frames frames, expected at least 5"; fail=1; }
for np in 2 3 4; do
  h5diff -r "$work/np1/fabric.h5" "$work/np$np/fabric.h5" >"$work/diff$np.log" 2>&1; rc=$?
  n=$(grep -c "^dataset" "$work/diff$np.log")
  if [[ $rc -eq 0 && $n -ge $((6 * frames + 2)) ]]; then echo "PASS h5diff: fabric.h5 on $np ranks == 1 rank ($n datasets, all attributes)"
  else echo "FAIL h5diff: fabric.h5 on $np ranks differs from 1 rank (exit $rc, $n datasets compared)"; grep -v "^0 differences\|^dataset\|^attribute" "$work/diff$np.log" | head -10; fail=1; fi
  if cmp -s "$work/np1/fabric.xmf" "$work/np$np/fabric.xmf"; then echo "PASS fabric.xmf on $np ranks == 1 rank"
  else echo "FAIL fabric.xmf differs on $np ranks"; fail=1; fi
done
exit $fail
