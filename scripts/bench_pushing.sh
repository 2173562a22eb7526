#!/usr/bin/env bash
# The pushing test (inputs/pushing.yaml, 24 threads/cm, 15 load steps) by both paths, in one run
# of this script on 2 ranks: the quasi-static path balanced to 1e-8 is the reference curve; every
# row gives its wall time, its iterations (te steps, or Newton and Krylov), its force at 5, 10 and
# 15 mm of travel and its largest relative force error against the reference from 5 mm on, and
# the wall-time ratio of the explicit path as shipped to the row.
# usage: scripts/bench_pushing.sh [extra options for every run, e.g. -ends_per_cm 8 -picks_per_cm 8]
source "$(dirname "$0")/bench_env.sh"
ranks="${RANKS:-2}"; positive_ranks RANKS "$ranks"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
extra=("$@")

run() { # name, options...
  local name="$1"; shift
  mpiexec -n "$ranks" "$fabric" -scene "$here/inputs/pushing.yaml" -output_every 0 -quiet -output_dir "$work/$name" \
    "${extra[@]}" "$@" >"$work/$name.log" 2>&1 || {
    echo "bench_pushing.sh: run $name failed: $(fabric_error "$work/$name.log")" >&2
    exit 1
  }
}

# name|options; the first row is the reference
runs=("static_1e-8|-solver static -balance_tol 1e-8" "static|-solver static" "explicit|"
      "explicit_1e-3|-balance_tol 1e-3" "explicit_lin_1e-3|-predict linear -balance_tol 1e-3"
      "explicit_1e-4|-balance_tol 1e-4 -max_inner_steps 400000")
rows=()
for r in "${runs[@]}"; do
  rows+=("${r%%|*}")
  # shellcheck disable=SC2086
  run "${r%%|*}" ${r#*|}
  # the error is taken from 5 mm of travel on: the reference must reach it (max() of nothing: a traceback)
  if ((${#rows[@]} == 1)) && ! awk -F, 'NR > 1 && $3 >= 5 - 1e-9 {ok = 1} END {exit !ok}' "$work/${r%%|*}/curve.csv"; then
    echo "bench_pushing.sh: the reference run reaches no load step at 5 mm of travel or more: no force error from 5 mm on" >&2; exit 1
  fi
done

printf '%-17s %8s %9s %8s %7s %10s %10s %10s %10s %9s %9s\n' run balanced wall_s te_steps newton krylov F5_N F10_N F15_N err_5mm+ speedup
t_ref="$(summary_key "$work/explicit" wall_s)"
for r in "${rows[@]}"; do
  /usr/bin/python3 - "$work/static_1e-8/curve.csv" "$work/$r/curve.csv" "$r" "$(summary_key "$work/$r" wall_s)" "$(summary_key "$work/$r" te_steps)" \
    "$(summary_key "$work/$r" nonlinear_iterations)" "$(summary_key "$work/$r" linear_iterations)" "$(summary_key "$work/$r" converged)" "$t_ref" <<'PY'
import csv, sys
ref = {round(float(r["travel_mm"]), 6): float(r["force_N"]) for r in csv.DictReader(open(sys.argv[1]))}
rows = {round(float(r["travel_mm"]), 6): float(r["force_N"]) for r in csv.DictReader(open(sys.argv[2]))}
name, wall, te, nl, li, conv, t_ref = sys.argv[3:10]
err = max(abs(f - ref[t]) / abs(ref[t]) for t, f in rows.items() if t >= 5 - 1e-9)
at = lambda mm: f"{rows[float(mm)]:.4f}" if float(mm) in rows else "-"  # no load step at that travel
te = te if te not in ("", "0") else "-"
print(f"{name:<17} {conv or '-':>8} {float(wall):9.2f} {te:>8} {nl or '-':>7} {li or '-':>10} {at(5):>10} {at(10):>10} "
      f"{at(15):>10} {100 * err:8.3f}% {float(t_ref) / float(wall):9.2f}")
PY
done
