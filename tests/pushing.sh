#!/usr/bin/env bash
# pushing.sh FABRIC SCENE: the ball burst test (inputs/pushing.yaml) on a coarser grid (8 threads/cm,
# 10 load steps to 15 mm): the force on the ball rises with its travel; the deformed fabric keeps the
# set-up's mirror symmetries, and the 4-fold one when warp and weft are the same yarn (crimp 8 %
# both), to 1e-6 relative (tests/check_pushing.py); positions bit-identical on 1 and 2 ranks.
set -u
fabric="$1"; scene="$2"; here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
opts=(-scene "$scene" -quiet -ends_per_cm 8 -picks_per_cm 8 -load_steps 10 -output_every 0)
fail=0
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/a2" -positions_out "$work/a2.bin" || fail=1
/usr/bin/python3 "$here/check_pushing.py" "$work/a2/curve.csv" "$work/a2.bin" 49 49 || fail=1
mpiexec -n 1 "$fabric" "${opts[@]}" -output_dir "$work/a1" -positions_out "$work/a1.bin" || fail=1
if cmp -s "$work/a1.bin" "$work/a2.bin"; then echo "PASS positions bit-identical on 1 and 2 ranks"; else echo "FAIL positions differ on 1 and 2 ranks"; fail=1; fi
mpiexec -n 1 "$fabric" "${opts[@]}" -weft_crimp_pct 8 -output_dir "$work/s1" -positions_out "$work/s1.bin" || fail=1
/usr/bin/python3 "$here/check_pushing.py" "$work/s1/curve.csv" "$work/s1.bin" 49 49 --fourfold || fail=1
exit $fail
