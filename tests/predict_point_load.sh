#!/usr/bin/env bash
# Prediction under a point load (the square net, 2 ranks): -predict extrapolate repeats the last
# converged increment (it returned at once, as the linear prediction must: there is no grip to
# follow), and the linear prediction leaves the front on (it turned the front off as if every
# point had been moved).
set -u
fabric="$1"; scene="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
opts=(-scene "$scene" -quiet -load_steps 6 -output_every 0)
fail=0
run() { local name="$1"; shift; mpiexec -n 2 "$fabric" "${opts[@]}" "$@" -output_dir "$work/$name" -positions_out "$work/$name.bin" || fail=1; }
key() { sed -n "s/^ *\"$2\": \\([^,]*\\),*$/\\1/p" "$work/$1/summary.json" | head -1; }
run none -predict none
run extrapolate -predict extrapolate
run front_none -predict none -front
run front_linear -predict linear -front
# extrapolate: the same balanced deflections (within -balance_tol 1e-6 of the scene, relative to the largest,
# tolerance 1e-5), in fewer te steps (the counts are deterministic)
if /usr/bin/python3 - "$work/none/curve.csv" "$work/extrapolate/curve.csv" <<'PY'; then :; else fail=1; fi
import csv, sys
a, b = (list(csv.DictReader(open(f))) for f in sys.argv[1:3])
top = max(abs(float(r["travel_mm"])) for r in a)
err = max(abs(float(x["travel_mm"]) - float(y["travel_mm"])) for x, y in zip(a, b)) / top
ok = len(a) == len(b) == 6 and err <= 1e-5 and all(r["balanced"] == "1" for r in a + b)
print(("PASS" if ok else "FAIL") + f" -predict extrapolate: the deflections of -predict none within {err:.2e} of the largest (tolerance 1e-5), every load step balanced")
sys.exit(not ok)
PY
te_none=$(key none te_steps); te_extra=$(key extrapolate te_steps)
if ((te_extra < te_none)); then echo "PASS -predict extrapolate: $te_extra te steps against $te_none without prediction"
else echo "FAIL -predict extrapolate: $te_extra te steps against $te_none without prediction (it predicted nothing?)"; fail=1; fi
up_none=$(key front_none point_updates); up_linear=$(key front_linear point_updates)
if cmp -s "$work/front_none.bin" "$work/front_linear.bin" && [[ "$up_none" == "$up_linear" ]]; then
  echo "PASS -front with -predict linear (nothing to follow): bit-identical to -predict none, $up_linear point updates"
else echo "FAIL -front with -predict linear: $up_linear point updates against $up_none with -predict none, or other positions"; fail=1; fi
exit $fail
