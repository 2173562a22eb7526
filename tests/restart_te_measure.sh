#!/usr/bin/env bash
# -te_measure's records survive a restart: a run checkpointed within a load step on 2 ranks and restarted
# on 3 writes the summary.json of the uninterrupted run on 1 rank (te_measure's states, first, last,
# tightest and worst; and the rest, apart from the wall-clock figures and the ranks). The checkpoint
# did not keep them: the restarted run's te_measure listed only the states measured after the
# restart ("states": 3 against 6 here).
set -u
fabric="$1"; inputs="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
. "$(dirname "$0")/restarted.sh" # checkpoint_at, restarted_from
opts=(-scene "$inputs/burst.yaml" -ends_per_cm 8 -picks_per_cm 8 -load_steps 4 -sphere_travel_mm 16 -max_inner_steps 2000
      -predict extrapolate -te_measure 1 -output_every 0 -quiet)
summary() { /usr/bin/python3 -c 'import json, sys
d = json.load(open(sys.argv[1]))
for k in ("wall_s", "point_updates_per_s", "options", "ranks", "restarted_from"): d.pop(k, None)
print(json.dumps(d, sort_keys=True, indent=1))' "$1"; }
mpiexec -n 1 "$fabric" "${opts[@]}" -output_dir "$work/a" -positions_out "$work/a.bin" >/dev/null || { echo "FAIL the uninterrupted run"; exit 1; }
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/b" -checkpoint_every_te 813 >/dev/null || { echo "FAIL the checkpointed run"; exit 1; }
at="$(checkpoint_at "$work/b/checkpoint.h5")"
rm -f "$work/b/curve.csv" "$work/b/summary.json" # compared: what the restart writes
mpiexec -n 3 "$fabric" "${opts[@]}" -output_dir "$work/b" -checkpoint_every_te 813 -restart "$work/b/checkpoint.h5" \
  -positions_out "$work/b.bin" >/dev/null || { echo "FAIL the restarted run"; exit 1; }
fail=0
if [[ "$at" == *" within" && "$(restarted_from "$work/b")" == "$at" ]]; then echo "PASS the run continued from its checkpoint (load steps done, within the next: $at)"
else echo "FAIL the restart did not continue from the checkpoint: $at; summary.json: $(restarted_from "$work/b")"; fail=1; fi
if cmp -s "$work/a.bin" "$work/b.bin" && cmp -s "$work/a/curve.csv" "$work/b/curve.csv"; then echo "PASS positions and curve.csv: restarted on 3 ranks == uninterrupted on 1"
else echo "FAIL positions or curve.csv differ"; fail=1; fi
if diff <(summary "$work/a/summary.json") <(summary "$work/b/summary.json"); then
  echo "PASS summary.json (te_measure: $(grep -o '"states": [0-9]*' "$work/a/summary.json")): restarted == uninterrupted"
else echo "FAIL summary.json differs after the restart"; fail=1; fi
exit $fail
