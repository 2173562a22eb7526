#!/usr/bin/env bash
# restart_every.sh FABRIC SCENE: checkpoints within load steps, by te steps and by wall-clock time.
#   every_te  -checkpoint_every_te 2000 with yarns that break at load step 4, so that load step 4 is
#             relaxed again (a second round of the break loop, 20000 te steps): every checkpoint
#             until the end of that round is within it (-rupture_drop_pct 0: the test goes on past
#             the rupture; yarns breaking on the load step's state, -break_locate_pct 0: a load step that
#             locates a break writes no checkpoint within it). Killed with SIGKILL once the first one is
#             there, restarted on 3 ranks from 2: bit-identical to the uninterrupted run.
#   every_s   -checkpoint_every_s 0.05 on 1 rank (the run takes about 0.25 s): checkpoints within load
#             steps while the run goes on, which then ends as the run without them; restarted on 2
#             ranks from its last one, it ends bit-identical too, and its end line lists the checkpoint.h5 it kept.
#   killed while writing: -checkpoint_every_te 20 on 2 ranks, SIGKILL amid its writes: checkpoint.h5,
#             written aside and renamed, is the last complete one and restarts bit-identically.
# Compared: final positions, curve.csv, fabric.h5 (h5diff), fabric.xmf, summary.json's counters.
set -u
fabric="$1"; scene="$2"
. "$(dirname "$0")/kill_run.sh" # wait_for, kill_run, attr
. "$(dirname "$0")/restarted.sh" # checkpoint_at, restarted_from
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail=0
check() { if eval "$1"; then echo "PASS $2"; else echo "FAIL $2"; fail=1; fi; }
counters() { /usr/bin/python3 -c "import json; s = json.load(open('$1')); print(s['te_steps'], s['point_updates'], s['load_steps_done'], s['converged'])" 2>/dev/null; }
same() { # same REF DIR: what differs, "" if nothing
  local what=""
  cmp -s "$1/positions.bin" "$2/positions.bin" || what+=" positions"
  cmp -s "$1/curve.csv" "$2/curve.csv" || what+=" curve.csv"
  h5diff -r "$1/fabric.h5" "$2/fabric.h5" >/dev/null 2>&1 || what+=" fabric.h5"
  cmp -s "$1/fabric.xmf" "$2/fabric.xmf" || what+=" fabric.xmf"
  [[ "$(counters "$1/summary.json")" == "$(counters "$2/summary.json")" ]] || what+=" summary.json"
  echo "$what"
}
where() { echo "load step $(($(attr "$1" /load_step) + $(attr "$1" /within_load_step))), round $(attr "$1" /relax_round), te step $(attr "$1" /relax_te_step) of the round"; }

# ---- every_te: a checkpoint in the second round of the break loop
opts=(-scene "$scene" -quiet -gauge_mm 20 -width_mm 5 -load_steps 6 -output_every 1 -predict extrapolate
      -point_load_N 0,0,0.001 -warp_break_pct 0.5 -rupture_drop_pct 0 -break_locate_pct 0)
a="$work/te_whole" b="$work/te_killed"
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$a" -positions_out "$a/positions.bin" >/dev/null || { echo "FAIL the uninterrupted run failed"; exit 1; }
mpiexec -n 2 "$fabric" "${opts[@]}" -checkpoint_every_te 2000 -output_dir "$b" -positions_out "$b/positions.bin" >/dev/null 2>&1 &
pid=$!
wait_for "$pid" '[[ -e "$b/checkpoint.h5" ]]'
kill_run "$pid"
ck="$b/checkpoint.h5"
check '[[ ! -e $b/summary.json && "$(attr "$ck" /within_load_step)" == 1 && "$(attr "$ck" /load_step)" == 3 && "$(attr "$ck" /relax_round)" == 1 ]]' "every_te: killed with a checkpoint within load step 4, in the second round of its break loop ($(where "$ck"), $(attr "$ck" /te_steps) te steps in all)"
at="$(checkpoint_at "$ck")"
mpiexec -n 3 "$fabric" "${opts[@]}" -checkpoint_every_te 2000 -output_dir "$b" -positions_out "$b/positions.bin" -restart "$ck" >/dev/null 2>&1
rc=$?
what="$(same "$a" "$b")"
check '[[ $rc -eq 0 && -z "$what" && "$(restarted_from "$b")" == "$at" ]]' "every_te: restarted on 3 ranks from 2 (from $at, summary.json: $(restarted_from "$b")) == uninterrupted, bit for bit ($(counters "$a/summary.json"); exit $rc)${what:+; differ:$what}"
forces="$(awk -F, 'NR > 1 { printf "%s ", $4 }' "$a/curve.csv")"
check 'awk -F, '"'"'NR == 5 && $5 > 20000 { ok = 1 } END { exit !ok }'"'"' "$a/curve.csv"' "every_te: yarns broke at load step 4, which was relaxed again (inner steps $(awk -F, 'NR == 5 { print $5 }' "$a/curve.csv"); force by load step: $forces N)"

# ---- every_s: checkpoints on the clock change nothing, and the last one restarts
opts=(-scene "$scene" -gauge_mm 20 -width_mm 5 -load_steps 6 -elongation_pct 3 -predict none -max_inner_steps 3000
      -point_load_N 0,0,0.001 -balance_tol 1e-5 -output_every 1 -output_te_every 1000)
a="$work/s_whole" b="$work/s_clock"
mpiexec -n 1 "$fabric" "${opts[@]}" -quiet -output_dir "$a" -positions_out "$a/positions.bin" >/dev/null || { echo "FAIL the uninterrupted run failed"; exit 1; }
mpiexec -n 1 "$fabric" "${opts[@]}" -checkpoint_every_s 0.05 -output_dir "$b" -positions_out "$b/positions.bin" >"$work/clock.log" 2>&1
rc=$?
n=$(grep -c "^checkpoint at load step [0-9]*, te step [0-9]*: " "$work/clock.log")
wall=$(sed -n 's/.*"wall_s": \([0-9.]*\).*/\1/p' "$b/summary.json" 2>/dev/null)
what="$(same "$a" "$b")"
check '[[ $rc -eq 0 && $n -ge 1 && -z "$what" ]]' "every_s: $n checkpoints within load steps in ${wall:-?} s, the run ends as without them (exit $rc)${what:+; differ:$what}"
results="$(grep -m1 "^fabric: results in" "$work/clock.log")"
check '[[ "$results" == "fabric: results in $b/ (curve.csv, summary.json, fabric.h5 and fabric.xmf ("*" frames), checkpoint.h5)" ]]' "every_s: the end line lists the checkpoint.h5 only -checkpoint_every_s wrote ($results)"
ck="$b/checkpoint.h5"
last="$(where "$ck")"
mv "$b/positions.bin" "$b/positions.first.bin"
# -checkpoint_every past the last load step writes none, and the end line lists none (it listed checkpoint.h5)
mpiexec -n 1 "$fabric" "${opts[@]}" -load_steps 2 -checkpoint_every 5 -output_dir "$work/none" >"$work/none.log" 2>&1
rc=$?
results="$(grep -m1 "^fabric: results in" "$work/none.log")"
check '[[ $rc -eq 0 && ! -e "$work/none/checkpoint.h5" && "$results" == "fabric: results in $work/none/ (curve.csv, summary.json, fabric.h5 and fabric.xmf ("*" frames))" ]]' "checkpoint_every 5 of 2 load steps: no checkpoint.h5, none listed ($results)"
at="$(checkpoint_at "$ck")"
mpiexec -n 2 "$fabric" "${opts[@]}" -quiet -output_dir "$b" -positions_out "$b/positions.bin" -restart "$ck" >"$work/again.log" 2>&1
rc=$?
what="$(same "$a" "$b")"
check '[[ $rc -eq 0 && -z "$what" && "$(restarted_from "$b")" == "$at" ]]' "every_s: restarted on 2 ranks from its last checkpoint ($last; summary.json: $(restarted_from "$b")) == uninterrupted, bit for bit${what:+; differ:$what}"
results="$(grep -m1 "^fabric: results in" "$work/again.log")"
check '[[ -e "$ck" && "$results" == *", checkpoint.h5)" ]]' "every_s: the restart writes no checkpoint, keeps the one it restarted from and lists it ($results)"

# ---- killed while writing: a checkpoint every 20 te steps keeps the run writing most of the time; SIGKILL
# then mostly finds .checkpoint.h5.tmp half written, and checkpoint.h5 is still the last complete one
b="$work/s_write"
mpiexec -n 2 "$fabric" "${opts[@]}" -quiet -checkpoint_every_te 20 -output_dir "$b" -positions_out "$b/positions.bin" >/dev/null 2>&1 &
pid=$!
wait_for "$pid" '[[ -e "$b/checkpoint.h5" ]]'
sleep 0.5
kill_run "$pid"
ended=0; [[ -e "$b/summary.json" ]] && ended=1 # the run ended before the kill: nothing was tested
tmp="no checkpoint was being written"; [[ -e "$b/.checkpoint.h5.tmp" ]] && tmp="killed while writing .checkpoint.h5.tmp ($(stat -c %s "$b/.checkpoint.h5.tmp") bytes)"
ck="$b/checkpoint.h5"
last="$(where "$ck")"
at="$(checkpoint_at "$ck")"
mpiexec -n 2 "$fabric" "${opts[@]}" -quiet -output_dir "$b" -positions_out "$b/positions.bin" -restart "$ck" >"$work/write.log" 2>&1
rc=$?
what="$(same "$a" "$b")"
check '[[ $ended -eq 0 && $rc -eq 0 && -z "$what" && "$(restarted_from "$b")" == "$at" ]]' "killed with SIGKILL amid checkpoints every 20 te steps before its end ($tmp): checkpoint.h5 ($last; summary.json: $(restarted_from "$b")) restarts, == uninterrupted, bit for bit (exit $rc; ended before the kill: $ended)${what:+; differ:$what}"
[[ $rc -eq 0 ]] || head -3 "$work/write.log"
exit $fail
