#!/usr/bin/env bash
# The quasi-static path (-solver static, MODEL.md 14) against the explicit path and across ranks:
#  1. square net (inputs/square_net.yaml, 25 x 25): every load step balanced, and the loaded
#     crossing's deflection under 0.5 N is the explicit path's 0.564165069 mm (measured with
#     -balance_tol 1e-9 -speed_tol 1e-9 -max_inner_steps 2000000, docs/static.md) within 1e-6;
#  2. the square net balanced to 1e-12 on 1, 2 and 3 ranks: positions agree to 1e-10 relative
#     (Krylov sums round differently on different splits: bitwise identity is not claimed).
set -u
fabric="$1"; inputs="$2"
. "$(dirname "$0")/runs.sh" # $py, $work, $fail, run NP ARGS...

run 2 -scene "$inputs/square_net.yaml" -solver static -output_dir "$work/sq"
"$py" - "$work/sq/curve.csv" <<'PY' || fail=1
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
ok = all(float(r["residual"]) <= 1e-6 for r in rows)
w, ref = float(rows[-1]["travel_mm"]), 0.564165069
err = abs(w - ref) / ref
print(("PASS" if ok else "FAIL") + f" square net: {len(rows)} load steps balanced to 1e-6")
print(("PASS" if err <= 1e-6 else "FAIL") + f" square net deflection {w:.9f} mm vs explicit {ref} mm: relative {err:.2e} (tol 1e-6)")
sys.exit(0 if ok and err <= 1e-6 else 1)
PY

for np in 1 2 3; do
  run "$np" -scene "$inputs/square_net.yaml" -solver static -balance_tol 1e-12 -output_every 0 -output_dir "$work/r$np" -positions_out "$work/pos$np.bin"
done
"$py" - "$work"/pos1.bin "$work"/pos2.bin "$work"/pos3.bin <<'PY' || fail=1
import struct, sys
def read(f):
    b = open(f, "rb").read(); n = struct.unpack(">ii", b[:8])[1]
    return struct.unpack(">%dd" % n, b[8:8 + 8 * n])
p1 = read(sys.argv[1]); scale = max(abs(v) for v in p1); bad = 0
for np, f in ((2, sys.argv[2]), (3, sys.argv[3])):
    q = read(f); err = max(abs(x - y) for x, y in zip(p1, q)) / scale
    ok = len(q) == len(p1) and err <= 1e-10; bad |= not ok
    print(("PASS" if ok else "FAIL") + f" static positions on {np} ranks vs 1 rank: largest difference / largest coordinate {err:.2e} (tol 1e-10)")
sys.exit(1 if bad else 0)
PY
exit $fail
