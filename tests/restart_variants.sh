#!/usr/bin/env bash
# restart_variants.sh FABRIC SCENE: restarting from a checkpoint continues exactly whatever the
# run keeps between load steps and within one. For each variant, a run whose last checkpoint is at
# load step 4 of 6 is restarted from it into its own output directory (the frames it wrote after
# the checkpoint are dropped and written again) and must end bit-identical to an uninterrupted run;
# so must a run whose only checkpoint is within a load step (-checkpoint_every_te at 3/5 of the
# run's te steps), restarted from it (but for breaking: restart_every.sh):
#   paper      the paper's integrator (positions_old, velocities_old) with extrapolating
#              prediction (converged_positions, _prev), restarted on 1 rank from 2
#   breaking   yarns that break at load step 4 (broken segments, rebuilt on every rank's
#              ghosts), 2 ranks
#   te_frames  frames every 50 te steps (the frame list and counter), 3 ranks
#   sleeping   no prediction, the front and sleeping (the awake box and the force scale of
#              the last te step, the jaw's ramp), 2 ranks
#   bodies     the strip pressed by gravity onto a plane and a pedestal with friction (the
#              friction anchors of both bodies) and kinetic damping (the last kinetic energy),
#              2 ranks (the reaction columns of curve.csv are floating-point sums: the same
#              number of ranks)
# A checkpoint with nothing left to run (the end of the last load step) restarts into a run that only
# writes its summary: its wall_s counts the run before the restart (not 0), and the drape's
# drape_coefficient_pct and folds are those of the uninterrupted run (measured on the checkpoint's state).
set -u
fabric="$1"; scene="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
. "$(dirname "$0")/restarted.sh" # restarted_from
base=(-scene "$scene" -quiet -gauge_mm 20 -width_mm 5 -load_steps 6 -output_every 1)
fail=0
variant() {
  local name="$1" np="$2" np_restart="$3"; shift 3
  local a="$work/$name/whole" b="$work/$name/restarted"
  mpiexec -n "$np" "$fabric" "${base[@]}" "$@" -output_dir "$a" -positions_out "$a/positions.bin" >/dev/null 2>&1 || { echo "FAIL $name: the uninterrupted run failed"; fail=1; return; }
  mpiexec -n "$np" "$fabric" "${base[@]}" "$@" -output_dir "$b" -checkpoint_every 4 >/dev/null 2>&1 || { echo "FAIL $name: the checkpointed run failed"; fail=1; return; }
  mpiexec -n "$np_restart" "$fabric" "${base[@]}" "$@" -quiet false -output_dir "$b" -checkpoint_every 4 -positions_out "$b/positions.bin" -restart "$b/checkpoint.h5" >"$work/$name.log" 2>&1 || { echo "FAIL $name: the restart failed"; fail=1; return; }
  local what=""
  grep -q "restart from .*checkpoint.h5 at load step 4/6" "$work/$name.log" || what+=" (did not resume at load step 4)"
  cmp -s "$a/positions.bin" "$b/positions.bin" || what+=" positions"
  cmp -s "$a/curve.csv" "$b/curve.csv" || what+=" curve.csv"
  h5diff -r "$a/fabric.h5" "$b/fabric.h5" >/dev/null 2>&1 || what+=" fabric.h5"
  cmp -s "$a/fabric.xmf" "$b/fabric.xmf" || what+=" fabric.xmf"
  if [[ -z $what ]]; then echo "PASS $name: restart at load step 4 on $np_restart rank(s) == uninterrupted run on $np ($(h5ls "$a/fabric.h5/frames" | wc -l) frames; $(grep -o '"te_steps": [0-9]*' "$a/summary.json"))"
  else echo "FAIL $name: differs from the uninterrupted run in:$what"; fail=1; fi
  [[ $name == breaking ]] || within "$@" # within the break loop's second round: restart_every.sh
}
# within: the same variant with one checkpoint within a load step, at 3/5 of its te steps
within() {
  local te c="$work/$name/within"
  te=$(sed -n 's/.*"te_steps": \([0-9]*\).*/\1/p' "$a/summary.json"); te=$((te * 3 / 5))
  mpiexec -n "$np" "$fabric" "${base[@]}" "$@" -output_dir "$c" -checkpoint_every_te "$te" >/dev/null 2>&1 || { echo "FAIL $name within: the checkpointed run failed"; fail=1; return; }
  local at; at="$(h5dump -a /load_step -a /within_load_step -a /relax_round -a /relax_te_step "$c/checkpoint.h5" 2>/dev/null | sed -n 's/ *(0): //p' | tr '\n' ' ')"
  read -r done in round step <<<"$at"
  mpiexec -n "$np_restart" "$fabric" "${base[@]}" "$@" -output_dir "$c" -positions_out "$c/positions.bin" -restart "$c/checkpoint.h5" >/dev/null 2>&1 || { echo "FAIL $name within: the restart failed"; fail=1; return; }
  local what=""
  [[ "$in" == 1 ]] || what+=" (the checkpoint is not within a load step: $at)"
  [[ "$(restarted_from "$c")" == "$done within" ]] || what+=" (did not resume within load step $((done + 1)): summary.json's restarted_from $(restarted_from "$c"))"
  cmp -s "$a/positions.bin" "$c/positions.bin" || what+=" positions"
  cmp -s "$a/curve.csv" "$c/curve.csv" || what+=" curve.csv"
  h5diff -r "$a/fabric.h5" "$c/fabric.h5" >/dev/null 2>&1 || what+=" fabric.h5"
  cmp -s "$a/fabric.xmf" "$c/fabric.xmf" || what+=" fabric.xmf"
  if [[ -z $what ]]; then echo "PASS $name within: restart within load step $((done + 1)) (round $round, after its te step $step; -checkpoint_every_te $te) on $np_restart rank(s) == uninterrupted run on $np"
  else echo "FAIL $name within: differs from the uninterrupted run in:$what"; fail=1; fi
}
variant paper 2 1 -integrator paper -damping_ratio 0 -predict extrapolate -elongation_pct 3 -max_inner_steps 200 -early_exit 0
variant breaking 2 2 -predict extrapolate -point_load_N 0,0,0.001 -warp_break_pct 0.5
variant te_frames 3 3 -predict extrapolate -elongation_pct 3 -point_load_N 0,0,0.001 -output_te_every 50
variant bodies 2 2 -predict none -elongation_pct 1 -gravity 2,0,-9.81 -plane -plane_point_mm 0,0,-0.15 -pedestal_diameter_mm 4 -friction_mu 0.3 -integrator damped -kinetic_damping -max_inner_steps 400 -early_exit 0
variant sleeping 2 2 -predict none -front 1 -sleep_tol 1e-4 -elongation_pct 1 -point_load_N 0,0,0.001 -max_inner_steps 3000
# nothing left to run: a strip whose checkpoint is the last load step's, and the drape
nothing() {
  local name="$1" np="$2"; shift 2
  local a="$work/$name/whole" b="$work/$name/restarted"
  mpiexec -n "$np" "$fabric" "$@" -output_dir "$a" -checkpoint_every 2 >/dev/null 2>&1 || { echo "FAIL $name: the checkpointed run failed"; fail=1; return; }
  mkdir -p "$b" && cp "$a/checkpoint.h5" "$b/ck.h5"
  mpiexec -n "$np" "$fabric" "$@" -output_dir "$b" -restart "$b/ck.h5" >"$work/$name.log" 2>&1 || { echo "FAIL $name: the restart failed"; fail=1; return; }
  /usr/bin/python3 - "$a/summary.json" "$b/summary.json" "$(h5dump -a /wall_s "$b/ck.h5" 2>/dev/null | sed -n 's/ *(0): //p')" "$work/$name.log" <<'PY'
import json, re, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
ck_wall, log = float(sys.argv[3]), open(sys.argv[4]).read()
done = re.search(r"done in ([0-9.]+) s: .*, ([0-9.e+-]+) point updates/s", log)
keys = [k for k in ("te_steps", "point_updates", "load_steps_done", "peak_force_N", "drape_coefficient_pct", "folds") if k in a]
bad = [f"{k} {a[k]} vs {b.get(k)}" for k in keys if a[k] != b.get(k)]
if not (b["wall_s"] >= ck_wall - 1e-6 and ck_wall > 0 and b["point_updates_per_s"] > 0):
    bad.append(f"wall_s {b['wall_s']} (checkpoint's {ck_wall}), point_updates_per_s {b['point_updates_per_s']}")
if b.get("restarted_from") != {"load_steps_done": a["load_steps_done"], "within_load_step": False}:
    bad.append(f"restarted_from {b.get('restarted_from')}: not the last load step's checkpoint")
if not done or float(done[1]) <= 0 or float(done[2]) <= 0:
    bad.append("done line: " + (done[0] if done else "missing"))
what = ", ".join(f"{k} {b[k]}" for k in keys)
print(("FAIL " if bad else "PASS ") + f"{sys.argv[1].split('/')[-3]}: restart from the last load step's checkpoint (nothing left to run): "
      + (f"wall_s {b['wall_s']} >= the checkpoint's {ck_wall:.6f}, {what}" if not bad else "; ".join(bad)))
sys.exit(1 if bad else 0)
PY
  [[ $? -eq 0 ]] || fail=1
}
nothing nothing_strip 2 "${base[@]}" -predict none -elongation_pct 3 -load_steps 4 -output_every 0
nothing nothing_drape 2 -scene "$(dirname "$scene")/drape.yaml" -quiet -output_every 0 -load_steps 2 -max_inner_steps 1500
# the breaking variant must break yarns at load step 4, before the checkpoint: the restarted run
# only carries nothing after it if it got the broken segments back
forces="$(awk -F, 'NR > 1 { printf "%s ", $4 }' "$work/breaking/whole/curve.csv")"
if awk -F, 'NR == 4 && $4 < 1 { bad = 1 } NR > 4 && ($4 > 1e-3 || $4 < -1e-3) { bad = 1 } END { exit bad }' "$work/breaking/whole/curve.csv"; then echo "PASS breaking: the yarns broke at load step 4 (force by load step: $forces N)"
else echo "FAIL breaking: the yarns did not break at load step 4: force by load step: $forces N"; fail=1; fi
exit $fail
