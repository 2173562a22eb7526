#!/usr/bin/env bash
# restart_bad.sh FABRIC SCENE: a checkpoint that is damaged, foreign or of another scene is
# refused on 2 ranks with one clear message naming -restart and the file, a non-zero exit, within
# seconds (no hang), and the output directory it would append to is left as it was.
set -u
fabric="$1"; scene="$2"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
opts=(-scene "$scene" -quiet -gauge_mm 20 -width_mm 5 -load_steps 6)
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/run" -checkpoint_every 3 >/dev/null || { echo "FAIL the run that makes the checkpoint failed"; exit 1; }
ck="$work/run/checkpoint.h5"
printf "this is not HDF5\n" >"$work/text.h5"
head -c $(($(stat -c %s "$ck") / 2)) "$ck" >"$work/truncated.h5"
cp "$work/run/fabric.h5" "$work/results.h5"
fail=0
snapshot() { (cd "$work/run" && find . -type f -exec md5sum {} + | sort); }
before="$(snapshot)"
refuse() { # refuse NAME REGEX OPTIONS...: the run must fail with REGEX and leave run/ as it was
  local name="$1" regex="$2"; shift 2
  local log rc
  log="$(timeout 30 mpiexec -n 2 "$fabric" "$@" 2>&1)"; rc=$?
  local msg="$(grep -m1 "fabric: error" <<<"$log")"
  if [[ $rc -ne 0 && $rc -ne 124 ]] && grep -Eq -- "$regex" <<<"$log" && [[ "$(snapshot)" == "$before" ]]; then echo "PASS $name: exit $rc, $msg"
  else echo "FAIL $name: exit $rc (124 = hung), expected a message matching: $regex"; echo "$log" | head -5; fail=1; fi
}
refuse not_hdf5 "-restart .*text.h5: not an HDF5 file" "${opts[@]}" -output_dir "$work/run" -restart "$work/text.h5"
refuse truncated "-restart .*truncated.h5: the HDF5 file cannot be opened: it is damaged or truncated" "${opts[@]}" -output_dir "$work/run" -restart "$work/truncated.h5"
refuse not_a_checkpoint "-restart .*results.h5: not a fabric checkpoint" "${opts[@]}" -output_dir "$work/run" -restart "$work/results.h5"
refuse other_grid "-restart .*checkpoint.h5: the checkpoint is of another grid: 49 x 12 crossings there .*, 49 x 14 here" "${opts[@]}" -width_mm 6 -output_dir "$work/run" -restart "$ck"
refuse other_scene "-restart .*checkpoint.h5: the checkpoint is of another scene: warp_crimp = 0.08 there .*, 0.07 here" "${opts[@]}" -warp_crimp_pct 7 -output_dir "$work/run" -restart "$ck"
refuse other_program "-restart .*checkpoint.h5: the checkpoint is of another scene: load_steps = 6 there .*, 8 here" "${opts[@]}" -load_steps 8 -output_dir "$work/run" -restart "$ck"
refuse other_integrator "-restart .*checkpoint.h5: the checkpoint is of another scene: integrator = damped there .*, paper here" "${opts[@]}" -integrator paper -output_dir "$work/run" -restart "$ck"
# frames were written before the checkpoint: restarting into a directory without them is refused
refuse frames_missing "-restart .*checkpoint.h5: .*/elsewhere/fabric.h5, which holds the [0-9]+ frames written before the checkpoint, is missing" "${opts[@]}" -output_dir "$work/elsewhere" -restart "$ck"
[[ -e "$work/elsewhere" ]] && { echo "FAIL frames_missing: $work/elsewhere was created"; fail=1; }
# checkpoints need a directory to go to
refuse no_output_dir "-checkpoint_every 2 needs an output directory: -output_dir is none" "${opts[@]}" -output_dir none -checkpoint_every 2
# the checkpoint itself still restarts (so the refusals above were about what they say)
if mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/run" -restart "$ck" >/dev/null 2>&1 && [[ $(wc -l <"$work/run/curve.csv") -eq 7 ]]; then echo "PASS the same checkpoint restarts the run it belongs to"
else echo "FAIL the checkpoint does not restart its own run"; fail=1; fi
exit $fail
