#!/usr/bin/env bash
# energy_watch_ranks.sh WORK FABRIC ARGS...: the run of ARGS (a watched integrator, a checkpoint) on 1 and on 3
# ranks: the two checkpoints hold the same values but for the rank count, the wall time and the checksum of the
# attributes (the energy watch's sums were plain floating-point sums, whose last bits followed the ranks), and
# the watch has run
set -u
work="$1"
shift
rm -rf "$work"_1 "$work"_3
for n in 1 3; do
  mpiexec -n "$n" "$@" -output_dir "$work"_"$n" >/dev/null 2>&1 || { echo "FAIL the run on $n ranks"; exit 1; }
done
out=$(h5diff "$work"_1/checkpoint.h5 "$work"_3/checkpoint.h5 2>&1)
rc=$?
((rc <= 1)) || { echo "FAIL h5diff could not compare the checkpoints: $out"; exit 1; }
d=$(grep -v -E '<(ranks|wall_s|attributes_checksum) of|differences found' <<<"$out")
checks=$(h5dump -a /energy_watch_checks "$work"_1/checkpoint.h5 | grep -Eo '\(0\): [0-9]+' | grep -Eo '[0-9]+$')
[[ -z "$d" ]] || { echo "FAIL the checkpoints differ: $d"; exit 1; }
((${checks:-0} > 0)) || { echo "FAIL the energy watch did not run (energy_watch_checks ${checks:-none})"; exit 1; }
echo "PASS the same checkpoint on 1 and 3 ranks after $checks checks of the energy watch"
