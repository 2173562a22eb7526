#!/usr/bin/env bash
# The drape's weight in curve.csv against the model's masses (MODEL.md 4), worked out here from the options alone:
# each yarn segment between two crossings of the disc weighs tex (1 + crimp) x its spacing, and the specimen is
# lowered onto its support by gravity growing with the load steps (k/K of it at load step k of K). A 100 mm disc at
# 2 threads/cm: 21 x 21 crossings, those with (i-10)^2 + (j-10)^2 <= 10^2 (integers: exact); 20 tex warp at 8 %
# crimp, 30 tex weft at 5 %, 5 mm spacings. Tolerance 1e-8 relative (curve.csv prints 9 digits). On 2 ranks.
# The last row's drop_mm is the largest drop of a crossing, -z of the lowest one in -positions_out (the specimen
# starts flat at z = 0), to 1e-8 relative.
set -u
fail=0
fabric="$1"; scene="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
mpiexec -n 2 "$fabric" -quiet -scene "$scene" -gauge_mm 100 -width_mm 100 -disc_diameter_mm 100 -clamp_ring_mm 0,60 \
  -pedestal_diameter_mm 60 -warp_tex 20 -warp_crimp_pct 8 -weft_tex 30 -weft_crimp_pct 5 -gravity 0,0,-9.81 \
  -load_steps 4 -max_inner_steps 20 -output_every 0 -output_dir "$work/out" -positions_out "$work/pos.bin" >"$work/log" 2>&1 ||
  { cat "$work/log"; echo "FAIL the run failed"; exit 1; }
awk -F, '
  function inside(i, j) { return i >= 0 && i <= 20 && j >= 0 && j <= 20 && (i - 10)^2 + (j - 10)^2 <= 100 }
  BEGIN {
    for (i = 0; i <= 20; i++) for (j = 0; j <= 20; j++) {
      warp += inside(i, j) && inside(i + 1, j) # warp segments run along i, weft segments along j
      weft += inside(i, j) && inside(i, j + 1)
    }
    mass = warp * 20e-6 * 1.08 * 0.005 + weft * 30e-6 * 1.05 * 0.005
    printf "hand: %d warp and %d weft segments, %.9g kg\n", warp, weft, mass
  }
  NR == 1 { for (c = 1; c <= NF; c++) col[$c] = c; next }
  {
    k = $col["load_step"]; got = $col["weight_fz_N"]; want = -9.81 * mass * k / 4; rows++
    ok = (got - want) <= 1e-8 * -want && (want - got) <= 1e-8 * -want
    printf "%s load step %d: weight_fz_N %.9g N, expected %.9g N (k/4 of the weight)\n", ok ? "PASS" : "FAIL", k, got, want
    if (!ok) bad++
  }
  END { if (rows != 4) { print "FAIL " rows " rows in curve.csv, expected 4"; bad++ } exit bad > 0 }' "$work/out/curve.csv" ||
  fail=1
/usr/bin/python3 - "$work/out/curve.csv" "$work/pos.bin" <<'PY' || fail=1
import csv, struct, sys
rows = list(csv.DictReader(open(sys.argv[1])))
b = open(sys.argv[2], "rb").read(); n = struct.unpack(">ii", b[:8])[1]
z = struct.unpack(f">{n}d", b[8:8 + 8 * n])[2::3]
want, got = -1e3 * min(z), float(rows[-1]["drop_mm"])
ok = want > 0 and abs(got - want) <= 1e-8 * want
print(("PASS" if ok else "FAIL") + f" load step {rows[-1]['load_step']}: drop_mm {got:.9g} mm, expected {want:.9g} mm "
      "(-z of the lowest crossing in -positions_out, 1e-8 relative)")
sys.exit(0 if ok else 1)
PY
exit "$fail"
