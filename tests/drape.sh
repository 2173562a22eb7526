#!/usr/bin/env bash
# drape.sh FABRIC SCENE: the Cusick drape scene (inputs/drape.yaml) on 1 and 2 ranks: the flat
# specimen measures DC = 100 % and no fold; the draped specimen comes to rest (summary.json
# "converged": the load step met the force and the speed tolerance, no crossing faster than
# 1e-5 m/s); the drape coefficient of the default fabric lies in the handbooks' range for woven
# fabrics (30-80 %); summary.json's drape_coefficient_pct and folds, and the final positions,
# are identical on 1 and 2 ranks; at rest the forces on the supports add up to the specimen's
# weight, pedestal_fz + clamp_fz = weight_fz (curve.csv), to 1e-5 of the weight (it gives 1.5e-7).
set -u
fabric="$1"; scene="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail=0
# the measure itself, on the flat specimen (gravity off): DC = 100 % exactly (the specimen's area is
# measured the same way) and no fold
mpiexec -n 2 "$fabric" -scene "$scene" -quiet -output_every 0 -gravity 0,0,0 -load_steps 1 -max_inner_steps 1 -output_dir "$work/flat" >/dev/null || { echo "FAIL the flat run failed"; exit 1; }
dcf=$(sed -n 's/.*"drape_coefficient_pct": \([^,]*\),.*/\1/p' "$work/flat/summary.json"); ff=$(sed -n 's/.*"folds": \([^,]*\),.*/\1/p' "$work/flat/summary.json")
if [[ "$dcf" == "100" && "$ff" == "0" ]]; then echo "PASS flat specimen: drape coefficient $dcf %, $ff folds"; else echo "FAIL flat specimen: drape coefficient '$dcf' % (expected 100), '$ff' folds (expected 0)"; fail=1; fi
# without an output directory the run still ends with its end line (which names no curve.csv); the drape's travel is its drop,
# and its result the drape coefficient and folds (it said 'peak force 0 N'); the progress line has no force (it said
# 'force 0.0000 N')
out="$(mpiexec -n 2 "$fabric" -scene "$scene" -load_steps 1 -max_inner_steps 1 -output_dir none 2>&1)"
if echo "$out" | grep -Eq "^load step    1/1  drop +[0-9.]+ mm  N' " && echo "$out" | grep -q "^fabric: done in .*; drape coefficient [0-9.e+-]* %, [0-9]* folds, last load step at [0-9.e+-]* mm drop;" && ! echo "$out" | grep -q "travel\|curve.csv\|force"; then
  echo "PASS -output_dir none: the progress and end lines say drop: $(echo "$out" | grep "^fabric: done")"
else echo "FAIL -output_dir none: no end line, or the drape's drop called travel:"; echo "$out"; fail=1; fi
for np in 1 2; do
  mpiexec -n "$np" "$fabric" -scene "$scene" -quiet -output_every 0 -output_dir "$work/r$np" -positions_out "$work/r$np.bin" >/dev/null || { echo "FAIL the run on $np ranks failed"; exit 1; }
done
dc1=$(sed -n 's/.*"drape_coefficient_pct": \([^,]*\),.*/\1/p' "$work/r1/summary.json")
dc2=$(sed -n 's/.*"drape_coefficient_pct": \([^,]*\),.*/\1/p' "$work/r2/summary.json")
f1=$(sed -n 's/.*"folds": \([^,]*\),.*/\1/p' "$work/r1/summary.json")
f2=$(sed -n 's/.*"folds": \([^,]*\),.*/\1/p' "$work/r2/summary.json")
if awk -v d="$dc1" 'BEGIN { exit !(d >= 30 && d <= 80) }'; then echo "PASS drape coefficient $dc1 % within 30-80 % ($f1 folds)"; else echo "FAIL drape coefficient '$dc1' % not within 30-80 %"; fail=1; fi
for np in 1 2; do
  if grep -q '"converged": true' "$work/r$np/summary.json"; then echo "PASS at rest on $np ranks: the load step balanced, no crossing faster than the speed tolerance"; else echo "FAIL on $np ranks the drape did not come to rest (summary.json converged is not true)"; fail=1; fi
done
if [[ -n "$dc1" && "$dc1" == "$dc2" && "$f1" == "$f2" ]]; then echo "PASS 1 and 2 ranks: the same drape coefficient ($dc2 %) and folds ($f2)"; else echo "FAIL 1 rank: $dc1 % $f1 folds, 2 ranks: $dc2 % $f2 folds"; fail=1; fi
if awk -F, 'NR == 1 { for (c = 1; c <= NF; c++) col[$c] = c; next } { p = $col["pedestal_fz_N"]; k = $col["clamp_fz_N"]; w = $col["weight_fz_N"] } END { e = (p + k - w) / w; if (e < 0) e = -e; printf "pedestal %.6g N + clamp %.6g N = %.6g N, weight %.6g N, relative difference %.2e (tolerance 1e-5)\n", p, k, p + k, w, e; exit !(w < 0 && e <= 1e-5) }' "$work/r1/curve.csv"; then echo "PASS the supports carry the weight"; else echo "FAIL the forces on the supports do not add up to the weight"; fail=1; fi
if cmp -s "$work/r1.bin" "$work/r2.bin"; then echo "PASS positions bit-identical on 1 and 2 ranks"; else echo "FAIL positions differ on 1 and 2 ranks"; fail=1; fi
exit $fail
