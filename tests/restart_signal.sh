#!/usr/bin/env bash
# restart_signal.sh FABRIC SCENE: SIGTERM (a batch system at the wall-time limit) or SIGUSR1 in
# the middle of a load step: the run writes a checkpoint within the load step at its next te steps,
# says "fabric: SIGTERM: checkpoint written at load step K, te step N: restart with -restart
# DIR/checkpoint.h5" and exits with status 3; restarted from it, it ends bit-identical to an
# uninterrupted run on 1 rank: final positions, curve.csv, fabric.h5 (h5diff), fabric.xmf and the
# te step and point update counters of summary.json.
#   1 -> 1   SIGTERM to the rank
#   2 -> 3   SIGTERM to both ranks (as a batch system signals every process of the job), restarted
#            on 3 ranks
#   2 -> 2   SIGUSR1 to mpiexec, which Open MPI forwards to the ranks at once (SIGTERM to mpiexec
#            reaches the ranks only after -mca odls_base_sigkill_timeout seconds, 1 by default, and
#            is followed by SIGKILL as long after: docs/checkpoints.md)
# DIR holds an earlier run's summary.json and final positions (-positions_out): the stopped run leaves neither (they
# read as its own, finished), and says no end line
# (it gave the last load step's force and travel of a load step not yet run).
# The jaw's force in curve.csv is a sum over ranks, exact here: the jaw's crossings all lie on one
# rank on 1, 2 and 3 ranks.
set -u
fabric="$1"; scene="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
# no prediction, a transverse load and a tight balance: each load step runs its 3000 te steps
# (the jaw ramps over the first 300 of them), with te-step frames; 24 load steps, so that the run
# (about 0.06 s a load step on 2 idle ranks) is still going when the signal comes, 0.1-0.3 s after
# load step 2
# the damped scheme: its load steps take long enough for a signal to land within one (FIRE's restarts
# within a load step: restart_every)
opts=(-scene "$scene" -quiet -integrator damped -gauge_mm 20 -width_mm 5 -load_steps 24 -elongation_pct 3 -predict none
      -max_inner_steps 3000 -point_load_N 0,0,0.001 -balance_tol 1e-5 -output_every 1 -output_te_every 2100)
fail=0
check() { if eval "$1"; then echo "PASS $2"; else echo "FAIL $2"; fail=1; fi; }
attr() { h5dump -a "$2" "$1" 2>/dev/null | sed -n 's/ *(0): //p'; }
counters() { /usr/bin/python3 -c "import json; s = json.load(open('$1')); print(s['te_steps'], s['point_updates'], s['load_steps_done'], s['converged'])"; }

ref="$work/whole"
mpiexec -n 1 "$fabric" "${opts[@]}" -output_dir "$ref" -positions_out "$ref/positions.bin" >/dev/null || { echo "FAIL the uninterrupted run failed"; exit 1; }

# case NAME NP NP_RESTART SIGNAL TARGET DELAY: TARGET ranks (the ranks' pids) or mpiexec, DELAY seconds
# after load step 2 is done (so that the signal comes at various te steps of load step 3 or later)
# A signal that lands while a load step's results are written (its curve row and frames) is taken at that load
# step's end, not within one: the case is run again, the signal 37 ms later, up to 3 times.
case_() {
  local name="$1" np="$2" np2="$3" sig="$4" target="$5" delay="$6" d="$work/$1" attempt pid i ranks rc msg
  for attempt in 1 2 3; do
    rm -rf "$d"
    mkdir -p "$d" && echo '{"converged": true}' >"$d/summary.json" # an earlier run's: removed at the start
    cp "$ref/positions.bin" "$d/positions.bin" # an earlier run's final positions (-positions_out): removed too
    mpiexec -n "$np" "$fabric" "${opts[@]}" -output_dir "$d" -positions_out "$d/positions.bin" >"$work/$name.log" 2>&1 &
    pid=$!
    for ((i = 0; i < 3000; i++)); do
      [[ -e "$d/curve.csv" && $(wc -l <"$d/curve.csv") -ge 3 ]] && break
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.02
  done
  sleep "$delay"
  ranks=$(ps -o pid= --ppid "$pid")
  if ! kill -0 "$pid" 2>/dev/null; then
    echo "FAIL $name: the run ended before the signal (${delay} s after load step 2): it is too short for this test"
    fail=1; return
  fi
  if [[ $target == ranks ]]; then kill -"$sig" $ranks 2>/dev/null; else kill -"$sig" "$pid"; fi
  wait "$pid"; rc=$?
  for p in $ranks; do while kill -0 "$p" 2>/dev/null; do sleep 0.05; done; done
  msg="$(grep -m1 "fabric: SIG" "$work/$name.log")"
  [[ "$msg" == *"at the end of load step"* && $attempt -lt 3 ]] || break
  echo "note $name: the signal landed at a load step's end ($msg); again, 37 ms later"
  delay=$(awk -v t="$delay" 'BEGIN { print t + 0.037 }')
  done
  local k n; k=$(sed -n 's/.*at load step \([0-9]*\), te step \([0-9]*\):.*/\1/p' <<<"$msg"); n=$(sed -n 's/.*, te step \([0-9]*\):.*/\1/p' <<<"$msg")
  check '[[ $rc -eq 3 ]]' "$name: SIG$sig to the $target: exit status $rc (3: stopped after a checkpoint)"
  check '[[ "$msg" =~ ^"fabric: SIG$sig: checkpoint written at load step "[0-9]+", te step "[0-9]+": restart with -restart $d/checkpoint.h5"$ ]]' "$name: the run says: $msg"
  check '[[ ! -e $d/summary.json && ! -e $d/positions.bin && $(($(wc -l <"$d/curve.csv") - 1)) -eq $((k - 1)) ]]' "$name: stopped within load step $k (curve.csv has its $((k - 1)) rows before, no summary.json, no final positions)"
  check '! grep -Eq "^fabric: (done|results)" "$work/$name.log"' "$name: no end line (\"fabric: done ...\", \"fabric: results in ...\"): the run is not done"
  check '[[ "$(attr "$d/checkpoint.h5" /within_load_step)" == 1 && "$(attr "$d/checkpoint.h5" /load_step)" == $((k - 1)) && $((${n:-0} > 0 && ${n:-0} < 3000)) == 1 ]]' "$name: checkpoint.h5 is within load step $k after its te step $n ($(attr "$d/checkpoint.h5" /relax_te_step) te steps of round $(attr "$d/checkpoint.h5" /relax_round); ramp $(attr "$d/checkpoint.h5" /ramp_done)/$(attr "$d/checkpoint.h5" /ramp_steps))"
  mpiexec -n "$np2" "$fabric" "${opts[@]}" -quiet false -output_dir "$d" -positions_out "$d/positions.bin" -restart "$d/checkpoint.h5" >"$work/$name.restart.log" 2>&1
  rc=$?
  check '[[ $rc -eq 0 ]] && grep -q "restart from .*checkpoint.h5 within load step $k/24, after its te step $n " "$work/$name.restart.log"' "$name: restarted on $np2 rank(s) within load step $k after te step $n, ends normally (exit $rc)"
  local what=""
  cmp -s "$ref/positions.bin" "$d/positions.bin" || what+=" positions"
  cmp -s "$ref/curve.csv" "$d/curve.csv" || what+=" curve.csv"
  h5diff -r "$ref/fabric.h5" "$d/fabric.h5" >/dev/null 2>&1 || what+=" fabric.h5"
  cmp -s "$ref/fabric.xmf" "$d/fabric.xmf" || what+=" fabric.xmf"
  [[ "$(counters "$ref/summary.json")" == "$(counters "$d/summary.json" 2>/dev/null)" ]] || what+=" summary.json"
  check '[[ -z "$what" ]]' "$name: $np -> $np2 ranks == uninterrupted on 1 rank, bit for bit: positions, curve.csv, fabric.h5 ($(h5ls "$ref/fabric.h5/frames" | wc -l) frames), fabric.xmf, summary counters ($(counters "$ref/summary.json"))${what:+; differ:$what}"
}
case_ term_1_1 1 1 TERM ranks 0.1
case_ term_2_3 2 3 TERM ranks 0.3
case_ usr1_2_2 2 2 USR1 mpiexec 0.2
exit $fail
