#!/usr/bin/env bash
# The bodies' reactions are exact sums, the same on any number of ranks and any split, bit for bit:
# the pushing test's force on the ball (read by the ball burst's break detection) and the pedestal's
# force in curve.csv. They were floating-point sums over each rank's crossings: on 2 ranks the ball's
# force differed from 1 rank's in its last bit (0.10994974962596814 against ...812), which the
# checkpoint's curve and peak_force_N keep and the break detection compares; the drape's pedestal_fx_N,
# a sum of friction forces that nearly cancel, was -1.80610894e-10 on 1 rank, -1.80610898e-10 on 2.
# Compared here: curve.csv, the final positions, the checkpoint's peak_force_N and the checksum of its
# curve (every column as the run computed it), on 1, 2 and 3 ranks and 2 ranks split in columns.
set -u
fabric="$1"; inputs="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail=0
attr() { h5dump -m %.17g -a "$2" "$1" 2>/dev/null | sed -n 's/^ *(0): //p'; }
check() { # name, options...
  local name="$1"; shift
  local ref="" got
  for run in 1 2 3 2c; do
    np="${run%c}"; split=(); [[ $run == 2c ]] && split=(-da_processors_x 2 -da_processors_y 1)
    mpiexec -n "$np" "$fabric" "$@" "${split[@]}" -quiet -output_every 0 -checkpoint_every 1 \
      -output_dir "$work/$name$run" -positions_out "$work/$name$run.bin" >"$work/$name$run.log" 2>&1 ||
      { echo "FAIL $name on $run ranks: $(tail -n 1 "$work/$name$run.log")"; fail=1; continue; }
    got="$(attr "$work/$name$run/checkpoint.h5" /peak_force_N) $(attr "$work/$name$run/checkpoint.h5" /history/curve/checksum)"
    [[ $got =~ ^-?[0-9.e+-]+\ -?[0-9.e+-]+$ ]] || { echo "FAIL $name on $run ranks: no peak force and curve checksum in checkpoint.h5 ('$got')"; fail=1; continue; }
    if [[ -z "$ref" ]]; then ref="$got"; echo "$name on 1 rank: peak force, curve checksum: $ref"; continue; fi
    if [[ "$got" == "$ref" ]] && cmp -s "$work/${name}1.bin" "$work/$name$run.bin" &&
      cmp -s "$work/${name}1/curve.csv" "$work/$name$run/curve.csv"; then echo "PASS $name: $run ranks == 1 rank (bit-identical)"
    else echo "FAIL $name: $run ranks: '$got', 1 rank: '$ref'"; diff "$work/${name}1/curve.csv" "$work/$name$run/curve.csv"; fail=1; fi
  done
}
check ball -scene "$inputs/pushing.yaml" -ends_per_cm 8 -picks_per_cm 8 -load_steps 2 -sphere_travel_mm 3 -max_inner_steps 1500
check pedestal -scene "$inputs/drape.yaml" -gauge_mm 150 -width_mm 150 -disc_diameter_mm 150 -clamp_ring_mm 0,90 \
  -pedestal_diameter_mm 90 -max_inner_steps 1500 -load_steps 2 -integrator paper -friction_mu 0.3
exit $fail
