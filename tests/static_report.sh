#!/usr/bin/env bash
# static_report.sh FABRIC INPUTS: what the quasi-static path reports, against its own curve.csv and
# solver log (exact invariants; mutation testing found them unchecked):
#  1. a bias specimen pulled out and back (-grip_path_mm 2,0,0,1,0,0: the force rises to load step 5,
#     then falls), balanced, and with -snes_max_it 3 (no load step balances; the largest force, at load
#     step 8, from an unbalanced state): summary.json's max_force_N is the largest force_N of curve.csv
#     (not the last: the balanced run's is at load step 5), elongation_at_max_force_pct that row's
#     elongation, max_force_balanced that row's balanced; nonlinear_iterations is the sum of inner_steps;
#     every row's balanced is its residual <= -balance_tol (rows within 1e-5 relative of the tolerance
#     skipped: %.6e rounding); converged is every row balanced; solver is "static" and integrator null;
#     solver_options holds -snes_max_it 3 in the run given it and nothing in the other;
#  2. runs cut by -checkpoint_every and restarted end as the uninterrupted ones: final positions bit for
#     bit, curve.csv identical and summary.json the same but for wall_s, point_updates_per_s: the run out
#     and back at -snes_max_it 8 cut after its maximum force (whether it balanced: max_force_balanced
#     false), the pull out and back at -snes_max_it 5 cut after an unbalanced load step that followed
#     balanced ones (the Newton shift it ended with starts the next one), and a pull whose first two load steps did not balance, cut after
#     load step 5 (converged false, though every load step after the restart balances);
#  3. a failed solve retried (-snes_linesearch_type basic -ksp_type preonly -pc_type lu: 8 attempts,
#     each taking Newton steps, then the numerical failure), and the square net from -snes_shift_start 0
#     (a retry, every load step balanced): nonlinear_iterations is the number of Newton steps that
#     -snes_monitor printed (its lines less its iteration-0 lines), every attempt's counted;
#  4. the residual column: an uncrimped linear strip without gravity, bending or shear left at its first guess
#     (-predict none -snes_max_it 0: only the jaw's crossings moved), where the crossing next to the moving jaw
#     carries the whole tension of the one stretched segment, the largest: residual = |F|max / Tmax = 1 on every
#     row to 1e-6 (%.6e: 1.000000e+00), balanced 0, converged false.
set -u
fabric="$1"; inputs="$2"
. "$(dirname "$0")/runs.sh" # $py, $work, $fail, run NP ARGS...

bias=(-scene "$inputs/bias.yaml" -gauge_mm 20 -width_mm 10 -ends_per_cm 8 -picks_per_cm 8 -load_steps 8
  -grip_path_mm 2,0,0,1,0,0 -solver static -output_every 0)

invariants() { # DIR LABEL
  "$py" - "$work/$1" "$2" <<'PY' || fail=1
import csv, json, sys
d, label = sys.argv[1], sys.argv[2]
rows = list(csv.DictReader(open(d + "/curve.csv")))
s = json.load(open(d + "/summary.json"))
tol = s["options"]["balance_tol"]
f = [float(r["force_N"]) for r in rows]
k = max(range(len(f)), key=lambda i: f[i])
bal = [r["balanced"] == "1" for r in rows]
checks = [
    (len(rows) == 8 and s["load_steps_done"] == 8, f"8 rows, load_steps_done {s['load_steps_done']}"),
    (s["max_force_N"] == f[k], f"max_force_N {s['max_force_N']} = the largest force_N {f[k]} (load step {k + 1}; last {f[-1]})"),
    (s["elongation_at_max_force_pct"] == float(rows[k]["elongation_pct"]),
     f"elongation_at_max_force_pct {s['elongation_at_max_force_pct']} = load step {k + 1}'s {rows[k]['elongation_pct']}"),
    (s["max_force_balanced"] == bal[k], f"max_force_balanced {s['max_force_balanced']} = load step {k + 1}'s balanced"),
    (s["nonlinear_iterations"] == sum(int(r["inner_steps"]) for r in rows),
     f"nonlinear_iterations {s['nonlinear_iterations']} = the sum of inner_steps {sum(int(r['inner_steps']) for r in rows)}"),
    (all(b == (float(r["residual"]) <= tol) for r, b in zip(rows, bal) if abs(float(r["residual"]) / tol - 1) > 1e-5),
     f"balanced = residual <= {tol} on every row: {[(r['residual'], r['balanced']) for r in rows]}"),
    (s["converged"] == all(bal), f"converged {s['converged']} = every row balanced ({sum(bal)} of {len(bal)})"),
    (s["solver"] == "static" and s["integrator"] is None, f"solver {s['solver']!r}, integrator {s['integrator']}"),
]
for ok, what in checks: print(("PASS " if ok else "FAIL ") + label + ": " + what)
sys.exit(0 if all(ok for ok, _ in checks) else 1)
PY
}

# 1. out and back, balanced and not
run 1 "${bias[@]}" -output_dir "$work/out_back"
invariants out_back "balanced"
run 1 "${bias[@]}" -snes_max_it 3 -output_dir "$work/unbal"
invariants unbal "-snes_max_it 3"
"$py" -c "import json, sys; s = json.load(open(sys.argv[1])); sys.exit(not (s['converged'] is False and s['max_force_balanced'] is False))" \
  "$work/unbal/summary.json" && echo "PASS -snes_max_it 3: converged false, max_force_balanced false" \
  || { echo "FAIL -snes_max_it 3: not the unbalanced run this test needs"; fail=1; }
# the solver options given are in summary.json (the scene's options hold none of them), and none where none was given
"$py" -c "import json, sys; a, b = (json.load(open(f))['solver_options'] for f in sys.argv[1:3]); print(a, b); sys.exit(not (a == {'snes_max_it': '3'} and b == {}))" \
  "$work/unbal/summary.json" "$work/out_back/summary.json" && echo "PASS solver_options: -snes_max_it 3 in the run given it, none in the other" \
  || { echo "FAIL solver_options: not the solver options given"; fail=1; }

# 2. restarted runs end as the uninterrupted ones
same_after_restart() { # NAME CUT LABEL OPTIONS...: the run whole, and cut by -checkpoint_every CUT and restarted
  local name="$1" cut="$2" label="$3"; shift 3
  mkdir -p "$work/$name"
  run 1 "$@" -output_dir "$work/$name/whole" -positions_out "$work/$name/whole.bin"
  run 1 "$@" -output_dir "$work/$name/cut" -checkpoint_every "$cut"
  run 1 "$@" -output_dir "$work/$name/cut" -restart "$work/$name/cut/checkpoint.h5" -positions_out "$work/$name/cut.bin"
  cmp -s "$work/$name/whole.bin" "$work/$name/cut.bin" && cmp -s "$work/$name/whole/curve.csv" "$work/$name/cut/curve.csv" \
    && echo "PASS $label: positions bit for bit and curve.csv identical" \
    || { echo "FAIL $label: positions or curve.csv differ"; diff "$work/$name/whole/curve.csv" "$work/$name/cut/curve.csv"; fail=1; }
  "$py" - "$work/$name/whole/summary.json" "$work/$name/cut/summary.json" "$label" "$cut" <<'PY' || fail=1
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
skip = {"wall_s", "point_updates_per_s", "options", "restarted_from"}
diff = {k: (a.get(k), b.get(k)) for k in set(a) | set(b) if k not in skip and a.get(k) != b.get(k)}
print(("PASS" if not diff else "FAIL") + f" {sys.argv[3]}: summary.json as the uninterrupted run's (max_force_N {b.get('max_force_N')}, "
      f"max_force_balanced {b.get('max_force_balanced')}, converged {b.get('converged')}, nonlinear_iterations {b.get('nonlinear_iterations')}); differing: {diff}")
# the run continued from the checkpoint after load step CUT (a run from the start gives the same bits)
resumed = b.get("restarted_from") == {"load_steps_done": int(sys.argv[4]), "within_load_step": False} and a.get("restarted_from") is None
print(("PASS" if resumed else "FAIL") + f" {sys.argv[3]}: restarted_from {b.get('restarted_from')} (the uninterrupted run's {a.get('restarted_from')})")
sys.exit(1 if diff or not resumed else 0)
PY
}
# an unbalanced run cut after its maximum force: with -snes_max_it 8 load step 7 (5.388 N, unbalanced), load step 8
# below it (0.281 N), so that the restart carries the maximum and its max_force_balanced false from the checkpoint
same_after_restart peak 7 "-snes_max_it 8, restarted at load step 7" "${bias[@]}" -snes_max_it 8
"$py" - "$work/peak/whole/curve.csv" 7 <<'PY' || fail=1
import csv, sys
rows, cut = list(csv.DictReader(open(sys.argv[1]))), int(sys.argv[2])
f = [float(r["force_N"]) for r in rows]
k = f.index(max(f))
ok = int(rows[k]["load_step"]) <= cut < len(rows) and rows[k]["balanced"] == "0"
print(("PASS" if ok else "FAIL") + f" -snes_max_it 8: the maximum {f[k]:.9g} N at load step {rows[k]['load_step']} (balanced "
      f"{rows[k]['balanced']}), at or before the cut at {cut} of {len(rows)} and unbalanced, as the restart case needs")
sys.exit(0 if ok else 1)
PY
# out and back with -snes_max_it 5: load steps 4, 5 balance, 6 does not and ends with a shift (1.6e-7) from which
# load step 7's first Newton step starts
same_after_restart shift 6 "-snes_max_it 5, restarted at load step 6" "${bias[@]}" -snes_max_it 5
# a pull with -snes_max_it 6: load steps 1, 2 do not balance, 3 to 8 do (the restarted run's converged: false); a
# checkpoint every 5 load steps of 8 leaves one, after load step 5 (every 4 left the last at load step 8: nothing to run)
pull=("${bias[@]}"); pull[13]=2,0,0
same_after_restart pull 5 "a pull, -snes_max_it 6, restarted at load step 5" "${pull[@]}" -snes_max_it 6

# 3. every attempt's Newton steps counted
newton_count() { # DIR LABEL
  "$py" - "$work/$1/summary.json" "$work/$1.mon" "$2" <<'PY' || fail=1
import json, sys
s = json.load(open(sys.argv[1]))
lines = [l.split() for l in open(sys.argv[2]) if "SNES Function norm" in l]
its, solves = sum(1 for l in lines if l[0] != "0"), sum(1 for l in lines if l[0] == "0")
ok = s["nonlinear_iterations"] == its and its > 0
print(("PASS" if ok else "FAIL") + f" {sys.argv[3]}: nonlinear_iterations {s['nonlinear_iterations']} = the {its} Newton steps of -snes_monitor ({solves} solves)")
sys.exit(0 if ok else 1)
PY
}
mpiexec -n 1 "$fabric" -quiet -scene "$inputs/square_net.yaml" -solver static -snes_shift_start 0 -snes_linesearch_type basic \
  -ksp_type preonly -pc_type lu -output_dir "$work/failed" -snes_monitor ":$work/failed.mon" >/dev/null 2>&1 \
  && { echo "FAIL the failing solve did not stop the run"; fail=1; }
newton_count failed "a failed solve, 8 attempts"
run 1 -scene "$inputs/square_net.yaml" -solver static -snes_shift_start 0 -output_dir "$work/shift0" -output_every 0 \
  -snes_monitor ":$work/shift0.mon"
newton_count shift0 "the square net from -snes_shift_start 0"

# 4. the residual at the first guess of a linear strip: exactly 1
run 1 -scene "$inputs/strip_warp.yaml" -gravity 0,0,0 -warp_break_pct 0 -weft_break_pct 0 -yarns 10 -gauge_mm 20 \
  -warp_crimp_pct 0 -warp_compression_ratio 1 -bending 0 -shear 0 -elongation_pct 2 -load_steps 4 -predict none \
  -solver static -snes_max_it 0 -output_every 0 -output_dir "$work/first_guess"
"$py" - "$work/first_guess" <<'PY' || fail=1
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/curve.csv")))
s = json.load(open(sys.argv[1] + "/summary.json"))
ok = len(rows) == 4 and all(abs(float(r["residual"]) - 1) <= 1e-6 and r["balanced"] == "0" for r in rows) and s["converged"] is False
print(("PASS" if ok else "FAIL") + f" a linear strip at its first guess: residual 1 (to 1e-6), balanced 0 on every row: "
      f"{[(r['residual'], r['balanced']) for r in rows]}, converged {s['converged']}")
sys.exit(0 if ok else 1)
PY
exit $fail
