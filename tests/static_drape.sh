#!/usr/bin/env bash
# static_drape.sh FABRIC SCENE: the drape (inputs/drape.yaml, 2 threads/cm) by the quasi-static path's
# SNES on 1 rank, where most segments end compressed: the tangent keeps their negative geometric part
# (the exact Hessian) once the balance ratio is below -static_exact_tangent (0.1), else drops it (the
# tension field). Checked:
#  1. with the defaults and -snes_max_it 1000 the load step balances; at rest the supports carry the
#     weight, pedestal_fz + clamp_fz = weight_fz, to 1e-5 of the weight (the balance test's 1e-6 of the
#     largest tension leaves 1e-8 of it), and the drape coefficient lies in the handbooks' range for
#     woven fabrics (30-80 %);
#  2. -info: every Newton step's tangent is the exact one where its ratio is below 0.1 and the tension
#     field where it is not, and the exact one was used;
#  3. with -static_exact_tangent 0, and with -snes_convex_tangent 1 (which drops the part in any case), no
#     tangent is chosen by its ratio (5 Newton steps an attempt: the choice shows at the first).
set -u
fabric="$1"; scene="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail=0
run() { # run NAME OPTIONS...: the log in $work/NAME.log, the outputs in $work/NAME
  local name="$1"; shift
  "$fabric" -scene "$scene" -solver static -snes_max_it 1000 -output_every 0 -output_dir "$work/$name" -info :sys "$@" \
    > "$work/$name.log" 2>&1 || { echo "FAIL the run $name failed:"; tail -5 "$work/$name.log"; exit 1; }
}
run exact
if grep -q "^fabric: done in .*every load step balanced" "$work/exact.log"; then
  echo "PASS balanced: $(grep '^fabric: done in' "$work/exact.log")"
else echo "FAIL the load step did not balance: $(grep '^fabric: done in' "$work/exact.log")"; fail=1; fi
if awk -F, 'NR == 1 { for (c = 1; c <= NF; c++) col[$c] = c; next } { p = $col["pedestal_fz_N"]; k = $col["clamp_fz_N"]; w = $col["weight_fz_N"] } END { e = (p + k - w) / w; if (e < 0) e = -e; printf "pedestal %.6g N + clamp %.6g N = %.6g N, weight %.6g N, relative difference %.2e (tolerance 1e-5)\n", p, k, p + k, w, e; exit !(w < 0 && e <= 1e-5) }' "$work/exact/curve.csv"; then
  echo "PASS the supports carry the weight"
else echo "FAIL the forces on the supports do not add up to the weight"; fail=1; fi
dc=$(sed -n 's/.*"drape_coefficient_pct": \([^,]*\),.*/\1/p' "$work/exact/summary.json")
if awk -v d="$dc" 'BEGIN { exit !(d >= 30 && d <= 80) }'; then echo "PASS drape coefficient $dc % within 30-80 %"
else echo "FAIL drape coefficient '$dc' % not within 30-80 %"; fail=1; fi
# each ChooseTangent line: "tangent at balance ratio R: exact" or "...: tension field"
if awk '/tangent at balance ratio/ { r = $0; sub(/.*ratio /, "", r); sub(/:.*/, "", r); n++
         exact = ($0 ~ /: exact$/); field = ($0 ~ /: tension field$/)
         near = (r + 0 > 0.1 - 1e-6 && r + 0 < 0.1 + 1e-6) # printed to 6 digits: either side of 0.1
         if (!(exact || field) || (!near && ((exact && !(r + 0 < 0.1)) || (field && r + 0 < 0.1)))) { print "wrong choice: " $0; bad = 1 }
         ne += exact }
       END { printf "%d tangents, %d exact (ratio below 0.1), %d the tension field\n", n, ne, n - ne; exit !(n > 0 && ne > 0 && !bad) }' "$work/exact.log"; then
  echo "PASS each tangent chosen by its ratio against 0.1"
else echo "FAIL the tangents' choice"; fail=1; fi
for opts in "-static_exact_tangent 0" "-snes_convex_tangent 1"; do
  # shellcheck disable=SC2086
  run off -snes_max_it 5 $opts
  if grep -q "tangent at balance ratio" "$work/off.log"; then
    echo "FAIL $opts: a tangent was chosen by its ratio: $(grep -m1 'tangent at balance ratio' "$work/off.log")"; fail=1
  elif ! grep -q "^fabric: done in" "$work/off.log"; then echo "FAIL $opts: no end line"; fail=1
  else echo "PASS $opts: no tangent chosen by its ratio"; fi
done
exit $fail
