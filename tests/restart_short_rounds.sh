#!/usr/bin/env bash
# restart_short_rounds.sh FABRIC NET_SCENE: SIGTERM to an explicit run whose load steps take one te
# step each (-max_inner_steps 1), so that its rounds never look at the signals within: the end of a
# load step looks once 16 te steps have passed since the last look. The run writes that load step's
# checkpoint, says "fabric: SIGTERM: checkpoint written at the end of load step K: restart with
# -restart DIR/checkpoint.h5" and exits with status 3 (before, it ran on to its last load step);
# restarted from it (2 ranks, as it ran) it ends bit-identical to the uninterrupted run: final
# positions, curve.csv and the te step count of summary.json.
set -u
fabric="$1"; scene="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
. "$(dirname "$0")/restarted.sh" # restarted_from
# 50 000 load steps of one te step each: about 4 s on 2 ranks uninterrupted
opts=(-scene "$scene" -quiet -load_steps 50000 -max_inner_steps 1 -output_every 0)
fail=0
check() { if eval "$1"; then echo "PASS $2"; else echo "FAIL $2"; fail=1; fi; }
counts() { /usr/bin/python3 -c "import json; s = json.load(open('$1')); print(s['te_steps'], s['load_steps_done'], s['converged'])"; }
attr() { h5dump -a "$2" "$1" 2>/dev/null | sed -n 's/ *(0): //p'; }

mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/whole" -positions_out "$work/whole.bin" >/dev/null \
  || { echo "FAIL the uninterrupted run failed"; exit 1; }

d="$work/cut"
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$d" -positions_out "$d.bin" >"$work/cut.log" 2>&1 &
pid=$!
for ((i = 0; i < 3000; i++)); do # until a few load steps are done
  [[ -e "$d/curve.csv" && $(wc -l <"$d/curve.csv") -ge 4 ]] && break
  kill -0 "$pid" 2>/dev/null || break
  sleep 0.02
done
ranks=$(ps -o pid= --ppid "$pid")
kill -0 "$pid" 2>/dev/null || { echo "FAIL the run ended before the signal: it is too short for this test"; exit 1; }
kill -TERM $ranks 2>/dev/null # the ranks, as a batch system signals every process of the job
wait "$pid"; rc=$?
for p in $ranks; do while kill -0 "$p" 2>/dev/null; do sleep 0.05; done; done
msg="$(grep -m1 "fabric: SIG" "$work/cut.log")"
k=$(sed -n 's/.*at the end of load step \([0-9]*\):.*/\1/p' <<<"$msg")
check "[[ $rc == 3 ]]" "SIGTERM to the ranks: exit status 3 (got $rc)"
check '[[ "$msg" =~ ^"fabric: SIGTERM: checkpoint written at the end of load step "[0-9]+": restart with -restart $d/checkpoint.h5"$ ]]' \
  "the message names the load step and the checkpoint: $msg"
check '[[ -n "$k" && $k -lt 50000 && $(($(wc -l <"$d/curve.csv") - 1)) -eq $k && ! -e $d/summary.json ]]' \
  "stopped after load step $k of 50000: curve.csv has its $k rows, no summary.json"
check '[[ "$(attr "$d/checkpoint.h5" /within_load_step)" == 0 && "$(attr "$d/checkpoint.h5" /load_step)" == "$k" ]]' \
  "checkpoint.h5 is at the end of load step $k"
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$d" -restart "$d/checkpoint.h5" -positions_out "$d.bin" >/dev/null 2>&1 \
  || { echo "FAIL the restarted run failed"; fail=1; }
check '[[ "$(restarted_from "$d")" == "$k at" ]]' "restarted: summary.json says the run continued from the end of load step $k ($(restarted_from "$d"))"
check "cmp -s '$work/whole.bin' '$d.bin'" "restarted: final positions bit-identical to the uninterrupted run"
check "cmp -s '$work/whole/curve.csv' '$d/curve.csv'" "restarted: curve.csv identical"
check "[[ \"$(counts "$work/whole/summary.json")\" == \"$(counts "$d/summary.json" 2>/dev/null)\" ]]" \
  "restarted: te steps, load steps done and the converged flag as uninterrupted ($(counts "$work/whole/summary.json"))"
exit $fail
