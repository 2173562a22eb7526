#!/usr/bin/env bash
# restart_kill.sh FABRIC SCENE: a run killed with SIGKILL after its first checkpoint (as a batch
# system does at the wall-time limit), then restarted with -restart, ends bit-identical to an
# uninterrupted run on the same number of ranks: final positions (-positions_out), curve.csv,
# every dataset and attribute of fabric.h5 (h5diff), fabric.xmf, and the te step and point
# update counters of summary.json.
set -u
fabric="$1"; scene="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
# te-step frames (continued after the restart), a transverse load (velocities and shear are not
# trivial), no prediction and at most 5000 te steps per load step (every load step takes as
# long, so that the run is still going when it is killed): a few seconds on 2 ranks
opts=(-scene "$scene" -quiet -gauge_mm 20 -width_mm 5 -load_steps 12 -elongation_pct 3 -predict none -max_inner_steps 5000
      -point_load_N 0,0,0.001 -balance_tol 1e-5 -checkpoint_every 2 -output_every 2 -output_te_every 1000)
fail=0
check() { if eval "$1"; then echo "PASS $2"; else echo "FAIL $2"; fail=1; fi; }

mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/whole" -positions_out "$work/whole/positions.bin" || { echo "FAIL the uninterrupted run failed"; exit 1; }

# the same run, killed after its first checkpoint (load step 2), once load step 3 is done (so
# that frames were written after the checkpoint): mpiexec and every rank at once, as a batch
# system does (the ranks are mpiexec's children, in process groups of their own)
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/killed" -positions_out "$work/killed/positions.bin" &
pid=$!
# (wait up to 2 minutes: under load, or in the sanitizer build, about 4 times slower, the first
# checkpoint can take longer than 20 s; the loop ends as soon as it is there)
for ((i = 0; i < 6000; i++)); do
  [[ -e "$work/killed/checkpoint.h5" && $(wc -l <"$work/killed/curve.csv") -ge 4 ]] && break
  sleep 0.02
done
ranks=$(ps -o pid= --ppid "$pid")
kill -KILL $ranks "$pid" 2>/dev/null
wait "$pid" 2>/dev/null; rc=$?
for p in $ranks; do while kill -0 "$p" 2>/dev/null; do sleep 0.05; done; done
rows_at_kill=$(($(wc -l <"$work/killed/curve.csv") - 1))
echo "killed with exit status $rc after $rows_at_kill of 12 load steps"
check '[[ $rc -ne 0 && ! -e $work/killed/summary.json && $rows_at_kill -lt 12 ]]' "the run was killed before its end (no summary.json, $rows_at_kill load steps in curve.csv)"

attr() { h5dump -a "$2" "$1" | sed -n 's/ *(0): //p'; }
echo "checkpoint at load step $(attr "$work/killed/checkpoint.h5" /load_step) with $(attr "$work/killed/checkpoint.h5" /frames) frames; $(h5ls "$work/killed/fabric.h5/frames" | wc -l) frames in fabric.h5 when killed"
at=$(attr "$work/killed/checkpoint.h5" /load_step)
check '[[ $at -ge 2 && $((at % 2)) -eq 0 ]]' "the checkpoint is of load step $at, one that -checkpoint_every 2 names (2, 4, ...)"
mpiexec -n 2 "$fabric" "${opts[@]}" -quiet false -output_dir "$work/killed" -positions_out "$work/killed/positions.bin" -restart "$work/killed/checkpoint.h5" >"$work/restart.log" 2>&1
rc=$?
check '[[ $rc -eq 0 ]]' "the restarted run ends normally"
check 'grep -q "restart from .*checkpoint.h5 at load step $at/12" "$work/restart.log"' "the restarted run resumed at the checkpoint's load step $at, not from the start"
check 'cmp -s "$work/whole/positions.bin" "$work/killed/positions.bin"' "final positions bit-identical to the uninterrupted run"
check 'cmp -s "$work/whole/curve.csv" "$work/killed/curve.csv"' "curve.csv identical ($(($(wc -l <"$work/whole/curve.csv") - 1)) load steps)"
h5diff -r "$work/whole/fabric.h5" "$work/killed/fabric.h5" >"$work/h5diff.log" 2>&1; rc=$?
check '[[ $rc -eq 0 ]]' "fabric.h5: h5diff finds no difference ($(grep -c '^dataset' "$work/h5diff.log") datasets compared, $(h5ls "$work/whole/fabric.h5/frames" | wc -l) frames)"
check 'cmp -s "$work/whole/fabric.xmf" "$work/killed/fabric.xmf"' "fabric.xmf identical"
counters() { /usr/bin/python3 -c "import json; s = json.load(open('$1')); print(s['te_steps'], s['point_updates'], s['load_steps_done'], s['converged'])"; }
check '[[ "$(counters "$work/whole/summary.json")" == "$(counters "$work/killed/summary.json")" ]]' "summary.json: te steps, point updates, load steps done, converged equal ($(counters "$work/whole/summary.json"))"
exit $fail
