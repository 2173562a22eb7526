#!/usr/bin/env bash
# Results must not depend on the number of ranks (MODEL.md 13):
#  1. positions after a fixed number of te steps (every force term on, out-of-plane load)
#     are bit-identical on 1, 2 and 3 ranks (the grid split in rows: the positions' ghosted home),
#     on 2 ranks split in columns and on a 2 x 2 split of 4 ranks (ghost columns: every point copied);
#  2. with early exit, the inner step count N' of every load step is the same;
#  1-2 run the default FIRE relaxation (its power F.v and norms are exact sums);
#  3. with kinetic damping (-integrator damped; velocity resets decided on a global sum of kinetic energies, taken
#     exactly in fixed point) positions after a fixed number of te steps are bit-identical.
set -u
fabric="$1"; scene="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fixed=(-scene "$scene" -quiet -output_every 0 -predict none -load_steps 2 -early_exit 0 -max_inner_steps 300 -point_load_N 0,0,0.02)
early=(-scene "$scene" -quiet -output_every 0 -predict none -gauge_mm 20 -width_mm 5 -load_steps 3 -elongation_pct 3 -balance_tol 1e-4 -point_load_N 0,0,0.001)
fail=0
run() { local np="$1"; shift; mpiexec -n "$np" "$fabric" "$@" || { echo "FAIL: run on $np ranks failed"; fail=1; }; }
for np in 1 2 3; do
  run "$np" "${fixed[@]}" -output_dir "$work/f$np" -positions_out "$work/pos$np.bin"
  run "$np" "${early[@]}" -output_dir "$work/e$np"
done
for np in 1 2 3; do run "$np" "${early[@]}" -integrator damped -kinetic_damping -early_exit 0 -max_inner_steps 500 -output_dir "$work/k$np" -positions_out "$work/kd$np.bin"; done
run 4 "${fixed[@]}" -da_processors_x 2 -da_processors_y 2 -output_dir "$work/f4" -positions_out "$work/pos4.bin"
run 2 "${fixed[@]}" -da_processors_x 2 -da_processors_y 1 -output_dir "$work/f2c" -positions_out "$work/pos2c.bin"
for np in 2 3 4 2c; do
  what="$np ranks"; [[ $np == 2c ]] && what="2 ranks split in columns"
  if cmp -s "$work/pos1.bin" "$work/pos$np.bin"; then echo "PASS positions after 600 te steps: $what == 1 rank (bit-identical)"
  else echo "FAIL positions differ between 1 rank and $what"; fail=1; fi
done
resets() { sed -n 's/.*"kinetic_damping_resets": \([0-9]*\).*/\1/p' "$1/summary.json"; }
for np in 2 3; do
  if cmp -s "$work/kd1.bin" "$work/kd$np.bin"; then echo "PASS kinetic damping, positions after 1500 te steps: $np ranks == 1 rank (bit-identical)"
  else echo "FAIL kinetic damping: positions differ between 1 and $np ranks"; fail=1; fi
done
r1="$(resets "$work/k1")"
if [[ -n "$r1" && "$r1" -gt 0 && "$r1" == "$(resets "$work/k2")" && "$r1" == "$(resets "$work/k3")" ]]; then echo "PASS kinetic damping reset the velocities $r1 times, as often on 1, 2 and 3 ranks"
else echo "FAIL kinetic damping resets: '$r1' on 1 rank, '$(resets "$work/k2")' on 2, '$(resets "$work/k3")' on 3 (expected > 0 and equal)"; fail=1; fi
steps1="$(cut -d, -f5 "$work/e1/curve.csv" | tr '\n' ' ')"
echo "inner steps per load step on 1 rank: $steps1"
for np in 2 3; do
  s="$(cut -d, -f5 "$work/e$np/curve.csv" | tr '\n' ' ')"
  if [[ "$s" == "$steps1" ]]; then echo "PASS inner step counts with early exit: $np ranks == 1 rank"
  else echo "FAIL inner step counts differ on $np ranks: $s"; fail=1; fi
done
exit $fail
