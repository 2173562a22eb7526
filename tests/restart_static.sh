#!/usr/bin/env bash
# restart_static.sh FABRIC NET_SCENE: the static path (-solver static) on SIGTERM, sent once load
# step 1 is done. The signal is looked at every second Newton step of a solve and at the end of
# each load step: the run writes the checkpoint of the iterate or of the load step, says "fabric:
# SIGTERM: checkpoint written at load step K, Newton step N: restart with -restart
# DIR/checkpoint.h5" (or "at the end of load step K") and exits with status 3; restarted from it (on
# 2 ranks, as it ran), it ends as the uninterrupted run: final positions bit for bit, curve.csv, and
# the Newton and Krylov counts of summary.json (the first guesses, the shift and the counts are in
# the checkpoint). restart_newton.sh stops a run within a solve for certain.
set -u
fabric="$1"; scene="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
. "$(dirname "$0")/kill_run.sh" # wait_for, term_ranks
. "$(dirname "$0")/restarted.sh" # checkpoint_at, restarted_from
# the square net at 80 mm (193 x 193 crossings): each of its 12 load steps takes about a second
opts=(-scene "$scene" -quiet -solver static -gauge_mm 80 -width_mm 80 -balance_tol 1e-9 -output_every 0)
fail=0
check() { if eval "$1"; then echo "PASS $2"; else echo "FAIL $2"; fail=1; fi; }
counts() { /usr/bin/python3 -c "import json; s = json.load(open('$1')); print(s['nonlinear_iterations'], s['linear_iterations'], s['load_steps_done'], s['converged'])"; }

mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/whole" -positions_out "$work/whole.bin" >/dev/null \
  || { echo "FAIL the uninterrupted run failed"; exit 1; }

d="$work/cut"
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$d" -positions_out "$d.bin" >"$work/cut.log" 2>&1 &
pid=$!
wait_for "$pid" "[[ -e $d/curve.csv && \$(wc -l <$d/curve.csv) -ge 2 ]]" # load step 1 is done
term_ranks "$pid"; rc=$?
check "[[ $rc == 3 ]]" "SIGTERM to the ranks: exit status 3 (got $rc)"
check "grep -Eq 'fabric: SIGTERM: checkpoint written at (the end of load step [0-9]+|load step [0-9]+, Newton step [0-9]+): restart with -restart $d/checkpoint.h5' '$work/cut.log'" \
  "the message names the load step and the checkpoint: $(grep -o 'written at [^:]*' "$work/cut.log")"
check "[[ -s $d/checkpoint.h5 && ! -e $d/summary.json ]]" "a checkpoint, no summary yet"
at="$(checkpoint_at "$d/checkpoint.h5")"
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$d" -restart "$d/checkpoint.h5" -positions_out "$d.bin" >/dev/null 2>&1 \
  || { echo "FAIL the restarted run failed"; fail=1; }
check "[[ \"$(restarted_from "$d")\" == \"$at\" ]]" "restarted: summary.json says the run continued from the checkpoint ($at; summary: $(restarted_from "$d"))"
check "cmp -s '$work/whole.bin' '$d.bin'" "restarted: final positions bit-identical to the uninterrupted run"
check "cmp -s '$work/whole/curve.csv' '$d/curve.csv'" "restarted: curve.csv identical"
check "[[ \"$(counts "$work/whole/summary.json")\" == \"$(counts "$d/summary.json" 2>/dev/null)\" ]]" \
  "restarted: Newton and Krylov counts, load steps done, converged: $(counts "$d/summary.json" 2>/dev/null)"
exit $fail
