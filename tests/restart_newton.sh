#!/usr/bin/env bash
# restart_newton.sh FABRIC NET_SCENE: the static path stopped within a load step's solve. The square
# net at 80 mm (193 x 193 crossings) in one load step from rest, 10 Newton steps on 2 ranks, with
# -checkpoint_every_s 1e-9 (a checkpoint at each look: every second Newton step). SIGTERM to both
# ranks once the first checkpoint is written: the run writes the iterate's checkpoint, says "fabric:
# SIGTERM: checkpoint written at load step 1, Newton step N: restart with -restart
# DIR/checkpoint.h5" and exits with status 3, with no summary yet. Restarted on 2 ranks, it ends as
# the uninterrupted run: final positions bit for bit, curve.csv, and the Newton and Krylov counts.
# Cut twice within one attempt (-snes_max_it), the same. Then TAO's trust region (-static_minimizer tao -tao_type ntr), whose own state within a solve
# (its radius) is not in the checkpoint: its restart from Newton step 5 (-tao_max_it 6 stops the
# first run) balances to the uninterrupted run's force, and its positions within 1e-9 of the net's
# size (balance_tol 1e-9).
set -u
fabric="$1"; scene="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
. "$(dirname "$0")/kill_run.sh" # wait_for, term_ranks
opts=(-scene "$scene" -solver static -gauge_mm 80 -width_mm 80 -balance_tol 1e-9 -output_every 0 -load_steps 1)
fail=0
check() { if eval "$1"; then echo "PASS $2"; else echo "FAIL $2"; fail=1; fi; }
counts() { /usr/bin/python3 -c "import json; s = json.load(open('$1')); print(s['nonlinear_iterations'], s['linear_iterations'], s['load_steps_done'], s['converged'])"; }

mpiexec -n 2 "$fabric" "${opts[@]}" -quiet -output_dir "$work/whole" -positions_out "$work/whole.bin" >/dev/null \
  || { echo "FAIL the uninterrupted run failed"; exit 1; }

d="$work/cut"
mpiexec -n 2 "$fabric" "${opts[@]}" -checkpoint_every_s 1e-9 -output_dir "$d" -positions_out "$d.bin" >"$work/cut.log" 2>&1 &
pid=$!
wait_for "$pid" "[[ -e $d/checkpoint.h5 ]]" # the first checkpoint (Newton step 2) is in place
term_ranks "$pid"; rc=$?
check "[[ $rc == 3 ]]" "SIGTERM to the ranks within the solve: exit status 3 (got $rc)"
check "grep -q 'fabric: SIGTERM: checkpoint written at load step 1, Newton step [0-9]*: restart with -restart $d/checkpoint.h5' '$work/cut.log'" \
  "the message names the Newton step and the checkpoint: $(grep -o 'Newton step [0-9]*: restart' "$work/cut.log")"
check "[[ -s $d/checkpoint.h5 && ! -e $d/summary.json ]]" "a checkpoint, no summary yet"
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$d" -restart "$d/checkpoint.h5" -positions_out "$d.bin" >"$work/restart.log" 2>&1 \
  || { echo "FAIL the restarted run failed"; fail=1; }
check "grep -q 'within load step 1/1, after its Newton step' '$work/restart.log'" "the restart says it goes on within the solve"
check "cmp -s '$work/whole.bin' '$d.bin'" "restarted: final positions bit-identical to the uninterrupted run"
check "cmp -s '$work/whole/curve.csv' '$d/curve.csv'" "restarted: curve.csv identical"
check "[[ \"$(counts "$work/whole/summary.json")\" == \"$(counts "$d/summary.json" 2>/dev/null)\" ]]" \
  "restarted: Newton and Krylov counts, load steps done, converged: $(counts "$d/summary.json" 2>/dev/null)"

# cut twice within one attempt, 1 rank, -snes_max_it 6 (the uninterrupted solve stops there, unbalanced): the last
# checkpoint of -snes_max_it 3 is at Newton step 2 (none after an attempt's last step), restarted with -snes_max_it 5 the
# last is at step 4 (the first attempt's steps, counted across the restart); restarted again: 6 Newton steps in all and
# the uninterrupted run's positions
six=("${opts[@]}" -quiet -snes_max_it 6)
"$fabric" "${six[@]}" -output_dir "$work/six_whole" -positions_out "$work/six_whole.bin" >/dev/null || { echo "FAIL the -snes_max_it 6 run failed"; fail=1; }
s="$work/six"
"$fabric" "${six[@]}" -checkpoint_every_s 1e-9 -snes_max_it 3 -output_dir "$s" >/dev/null 2>&1
n1=$(h5dump -a static_newton_steps "$s/checkpoint.h5" 2>/dev/null | sed -n 's/ *(0): //p')
"$fabric" "${six[@]}" -checkpoint_every_s 1e-9 -snes_max_it 5 -output_dir "$s" -restart "$s/checkpoint.h5" >/dev/null 2>&1
n2=$(h5dump -a static_newton_steps "$s/checkpoint.h5" 2>/dev/null | sed -n 's/ *(0): //p')
"$fabric" "${six[@]}" -output_dir "$s" -restart "$s/checkpoint.h5" -positions_out "$s.bin" >/dev/null 2>&1 || { echo "FAIL the second restart failed"; fail=1; }
check "[[ '$n1 $n2' == '2 4' ]]" "the checkpoints of the attempt: at Newton steps 2, then 4 (got $n1, $n2)"
check "cmp -s '$work/six_whole.bin' '$s.bin' && [[ \"\$(counts '$work/six_whole/summary.json')\" == \"\$(counts '$s/summary.json')\" ]]" \
  "restarted twice: the positions and counts of the uninterrupted run: $(counts "$s/summary.json" 2>/dev/null)"

# TAO: the checkpoint at Newton step 5, then the restart to the end
tao=(-static_minimizer tao -tao_type ntr)
mpiexec -n 2 "$fabric" "${opts[@]}" "${tao[@]}" -quiet -output_dir "$work/tao_whole" -positions_out "$work/tao_whole.bin" >/dev/null \
  || { echo "FAIL the uninterrupted TAO run failed"; exit 1; }
t="$work/tao_cut"
mpiexec -n 2 "$fabric" "${opts[@]}" "${tao[@]}" -quiet -checkpoint_every_s 1e-9 -tao_max_it 6 -output_dir "$t" >/dev/null 2>&1
mpiexec -n 2 "$fabric" "${opts[@]}" "${tao[@]}" -output_dir "$t" -restart "$t/checkpoint.h5" -positions_out "$t.bin" >"$work/tao_restart.log" 2>&1 \
  || { echo "FAIL the restarted TAO run failed"; fail=1; }
check "grep -q 'within load step 1/1, after its Newton step 5 ' '$work/tao_restart.log'" "TAO: restarted from Newton step 5"
check "/usr/bin/python3 -c \"
import csv, sys
import numpy as np
a = np.fromfile('$work/tao_whole.bin', dtype='>f8', offset=8); b = np.fromfile('$t.bin', dtype='>f8', offset=8)
rw = list(csv.DictReader(open('$work/tao_whole/curve.csv')))[-1]; rc = list(csv.DictReader(open('$t/curve.csv')))[-1]
ok = a.size == b.size and np.abs(a - b).max() <= 1e-9 * 0.08 and rc['balanced'] == '1' and abs(float(rw['force_N']) - float(rc['force_N'])) <= 1e-9 * float(rw['force_N'])
print('positions differ by at most %.3g m' % np.abs(a - b).max()); sys.exit(0 if ok else 1)\"" \
  "TAO: the restart balances to the same force and positions"
exit $fail
