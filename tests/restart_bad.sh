#!/usr/bin/env bash
# restart_bad.sh FABRIC SCENE: a checkpoint that is damaged, foreign or of another scene is
# refused on 2 ranks with one clear message naming -restart and the file, a non-zero exit, within
# seconds (no hang), and the output directory it would append to is left as it was. A byte flipped
# in the data of any array is refused by the array's checksum, naming it; a value of the attributes of /
# changed within its range, by their checksum.
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
refuse other_scene "-restart .*checkpoint.h5: the checkpoint is of another scene: warp_crimp_pct = 8 there .*, 7 here" "${opts[@]}" -warp_crimp_pct 7 -output_dir "$work/run" -restart "$ck"
refuse other_program "-restart .*checkpoint.h5: the checkpoint is of another scene: load_steps = 6 there .*, 8 here" "${opts[@]}" -load_steps 8 -output_dir "$work/run" -restart "$ck"
# a yarn table with the same last force and another row (its node count and last force were all that was compared)
law="$(dirname "$scene")/yarns/cotton_20tex.csv"
sed 's/^3.0000,190.621$/3.0000,170.000/' "$law" >"$work/law2.csv"
mpiexec -n 2 "$fabric" "${opts[@]}" -warp_law_csv "$law" -output_dir "$work/lawrun" -checkpoint_every 3 >/dev/null \
  || { echo "FAIL the run with a yarn table failed"; fail=1; }
refuse other_table "-restart .*checkpoint.h5: the checkpoint is of another scene: warp_law_csv_checksum = .* there .*, .* here" \
  "${opts[@]}" -warp_law_csv "$work/law2.csv" -output_dir "$work/lawrun" -restart "$work/lawrun/checkpoint.h5"
cmp -s "$law" "$work/law2.csv" && { echo "FAIL the changed table is the same file"; fail=1; }
refuse other_integrator "-restart .*checkpoint.h5: the checkpoint is of another scene: integrator = fire there .*, paper here" "${opts[@]}" -integrator paper -output_dir "$work/run" -restart "$ck"
# a damaged attribute that counts or indexes (rupture_step indexes the curve rows; the checkpoint is of the last
# of 6 load steps) is refused, naming it, not read past the arrays
setattr() { /usr/bin/python3 -c "import sys, h5py; f = h5py.File(sys.argv[1], 'r+'); f.attrs[sys.argv[2]] = float(sys.argv[3])" "$@"; }
for bad in "rupture_step 20 load steps done" "rupture_step 2.5 load steps done" "first_break_step -1 load steps" "first_break_i 1e9 crossings in x" "segments_broken nan segments of the grid"; do
  read -r attr value what <<<"$bad"
  cp "$ck" "$work/attr.h5" && setattr "$work/attr.h5" "$attr" "$value" || { echo "FAIL cannot set $attr"; fail=1; continue; }
  refuse "attr_${attr}_$value" "-restart .*attr.h5: damaged checkpoint: $attr = .* \\(a whole number from 0 to [0-9]+, $what\\)" "${opts[@]}" -output_dir "$work/run" -restart "$work/attr.h5"
done
# a damaged frame count: 2^31 - 1 was allocated on rank 0 alone before the list's length was looked at ("fabric: error:
# ReadHeader", the other rank waiting 10 s), and 0 beside the list restarted and dropped the earlier frames of fabric.h5
for bad in "2147483647 /history/frames does not hold 2147483647 frames" "0 frames = 0, yet /history/frames is there"; do
  read -r value what <<<"$bad"
  cp "$ck" "$work/attr.h5" && setattr "$work/attr.h5" frames "$value" || { echo "FAIL cannot set frames"; fail=1; continue; }
  refuse "attr_frames_$value" "-restart .*attr.h5: damaged checkpoint: $what" "${opts[@]}" -output_dir "$work/run" -restart "$work/attr.h5"
done
# a real counter that is not a finite number: a NaN grip travel ran and ended in "numerical instability" after removing
# the earlier summary.json, a NaN wall time ended "done in nan s" with exit 0
for bad in "grip_disp_m nan" "wall_s inf" "te_now_s nan" "peak_force_N -inf"; do
  read -r attr value <<<"$bad"
  cp "$ck" "$work/attr.h5" && setattr "$work/attr.h5" "$attr" "$value" || { echo "FAIL cannot set $attr"; fail=1; continue; }
  refuse "attr_${attr}_$value" "-restart .*attr.h5: damaged checkpoint: $attr = -?(nan|inf) is not a finite number" "${opts[@]}" -output_dir "$work/run" -restart "$work/attr.h5"
done
# a value changed within its range (1 ulp of a real, one more of a count) is refused by the checksum of the attributes of /
# (format 17): a changed te, FIRE step or time restarted and silently gave other results
nudge() { /usr/bin/python3 -c "import sys, h5py, numpy as np; f = h5py.File(sys.argv[1], 'r+'); v = f.attrs[sys.argv[2]]; f.attrs[sys.argv[2]] = np.nextafter(v, np.inf) if np.issubdtype(v.dtype, np.floating) else v + 1" "$@"; }
for attr in te_now_s fire_alpha fire_dt_s time_s fire_positive_steps kinetic_resets; do
  cp "$ck" "$work/attr.h5" && nudge "$work/attr.h5" "$attr" || { echo "FAIL cannot change $attr"; fail=1; continue; }
  refuse "attr_${attr}_nudged" "-restart .*attr.h5: damaged checkpoint: the checksum of the attributes of / .the counters and the relaxation's state. does not match" "${opts[@]}" -output_dir "$work/run" -restart "$work/attr.h5"
done
# -te_measure's counts (checkpoint format 16): out of their range they made summary.json's te / limit inf or nan
for bad in "te_measure_states -1 -1, te_measure_prev_load_step = [0-9]+" "te_measure_prev_load_step 7 [0-9]+, te_measure_prev_load_step = 7"; do
  read -r attr value what <<<"$bad"
  cp "$ck" "$work/attr.h5" && setattr "$work/attr.h5" "$attr" "$value" || { echo "FAIL cannot set $attr"; fail=1; continue; }
  refuse "attr_${attr}_$value" "-restart .*attr.h5: damaged checkpoint: te_measure_states = $what .0 to 6." "${opts[@]}" -output_dir "$work/run" -restart "$work/attr.h5"
done
# a checkpoint of the format before or after this fabric's is refused; a grid of another length (other_grid: another
# width); the load step, the place within it and the flag that says it is within one, out of their ranges (the
# checkpoint is at the end of the last load step, 6; -max_inner_steps is 20000)
setattrs() { /usr/bin/python3 -c "import sys, h5py; f = h5py.File(sys.argv[1], 'r+'); [f.attrs.__setitem__(k, float(v)) for k, v in zip(sys.argv[2::2], sys.argv[3::2])]" "$@"; }
format=$(/usr/bin/python3 -c "import sys, h5py; print(int(h5py.File(sys.argv[1], 'r').attrs['fabric_checkpoint']))" "$ck")
for v in $((format - 1)) $((format + 1)); do
  cp "$ck" "$work/attr.h5" && setattrs "$work/attr.h5" fabric_checkpoint "$v" || { echo "FAIL cannot set fabric_checkpoint"; fail=1; continue; }
  refuse "format_$v" "-restart .*attr.h5: checkpoint format $v, this fabric reads format $format" "${opts[@]}" -output_dir "$work/run" -restart "$work/attr.h5"
done
refuse other_grid_length "-restart .*checkpoint.h5: the checkpoint is of another grid: 49 x 12 crossings there .*, [0-9]+ x 12 here" "${opts[@]}" -gauge_mm 25 -output_dir "$work/run" -restart "$ck"
for bad in "load_step_0|load step 0 of 6|load_step 0" "load_step_6_within|load step 7 of 6|load_step 6 within_load_step 1 relax_te_step 5" \
           "within_2|within_load_step = 2|within_load_step 2" "te_step_0|te step 0 of round 0 within a load step of at most [0-9]+ te steps|within_load_step 1 relax_te_step 0 relax_round 0" \
           "te_step_max|te step 20000 of round 0 within a load step of at most 20000 te steps|within_load_step 1 relax_te_step 20000 relax_round 0" \
           "newton_explicit|a Newton step's checkpoint within a load step of an explicit run|within_load_step 1 relax_te_step 0 static_newton_steps 3" \
           "newton_at_end|static_newton_steps = 3, static_residual_norm0 = 0 at a load step's end|static_newton_steps 3" \
           "newton_negative|static_newton_steps = -1, static_residual_norm0 = 0 at a load step's end|static_newton_steps -1" \
           "newton_te_step|Newton step 3 of round 0, after 0 Newton steps, with te step 5|within_load_step 1 relax_te_step 5 static_newton_steps 3"; do
  IFS='|' read -r name what pairs <<<"$bad"
  cp "$ck" "$work/attr.h5" && setattrs "$work/attr.h5" $pairs || { echo "FAIL cannot set $pairs"; fail=1; continue; }
  refuse "attr_$name" "-restart .*attr.h5: damaged checkpoint: $what" "${opts[@]}" -output_dir "$work/run" -restart "$work/attr.h5"
done
# frames were written before the checkpoint: restarting into a directory without them is refused
refuse frames_missing "-restart .*checkpoint.h5: .*/elsewhere/fabric.h5, which holds the [0-9]+ frames written before the checkpoint, is missing" "${opts[@]}" -output_dir "$work/elsewhere" -restart "$ck"
[[ -e "$work/elsewhere" ]] && { echo "FAIL frames_missing: $work/elsewhere was created"; fail=1; }
# checkpoints need a directory to go to
refuse no_output_dir "-checkpoint_every 2 needs an output directory: -output_dir is none" "${opts[@]}" -output_dir none -checkpoint_every 2
refuse no_output_dir_te "-checkpoint_every_te 500 needs an output directory: -output_dir is none" "${opts[@]}" -output_dir none -checkpoint_every_te 500
refuse no_output_dir_s "-checkpoint_every_s 60.? needs an output directory: -output_dir is none" "${opts[@]}" -output_dir none -checkpoint_every_s 60
refuse negative_every_s "-checkpoint_every_s must be 0 .never. or a number of seconds, got -1" "${opts[@]}" -output_dir "$work/run" -checkpoint_every_s -1
refuse negative_every_te "-checkpoint_every_te must be 0 .never. or a number of te steps, got -5" "${opts[@]}" -output_dir "$work/run" -checkpoint_every_te -5

# A flipped byte in the data of any array is refused by its checksum, naming the array: a checkpoint
# that holds every array (the paper integrator's history, the extrapolation's, the friction anchors
# of a plane and a pedestal), each flipped at its first, a middle and its last value, in the low
# mantissa (one bit: a change of 1 ulp), the middle and the sign and exponent byte.
rich=(-scene "$scene" -quiet -gauge_mm 20 -width_mm 5 -load_steps 3 -elongation_pct 1 -integrator paper -damping_ratio 0
      -predict extrapolate -max_inner_steps 200 -early_exit 0 -gravity 2,0,-9.81 -plane -plane_point_mm 0,0,-0.15
      -pedestal_diameter_mm 4 -friction_mu 0.3)
mpiexec -n 2 "$fabric" "${rich[@]}" -output_dir "$work/rich" -checkpoint_every 2 >/dev/null || { echo "FAIL the run that makes the full checkpoint failed"; exit 1; }
rich_snapshot() { (cd "$work/rich" && find . -type f -exec md5sum {} + | sort); }
rich_before="$(rich_snapshot)"
# flip FILE DATASET WHICH BYTE MASK: XOR byte BYTE of value WHICH (first, middle, last) of the dataset's
# data with MASK where it lies in the file (contiguous or chunked, unfiltered); prints offset and values
flip() {
  /usr/bin/python3 - "$@" <<'PY'
import sys, h5py, numpy as np
file, path, which, byte, mask = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5], 0)
with h5py.File(file, "r") as f:
    d = f[path]
    n = d.size
    e = {"first": 0, "middle": n // 2 + 1, "last": n - 1}[which]
    idx = np.unravel_index(e, d.shape)
    before = d[idx]
    if d.chunks is None:
        off = d.id.get_offset() + e * d.dtype.itemsize
    else:
        corner = tuple((i // c) * c for i, c in zip(idx, d.chunks))
        info = d.id.get_chunk_info_by_coord(corner)
        assert info.filter_mask == 0 and not d.compression
        within = np.ravel_multi_index(tuple(i - c for i, c in zip(idx, corner)), d.chunks)
        off = info.byte_offset + within * d.dtype.itemsize
with open(file, "r+b") as fp:
    fp.seek(off + byte)
    b = fp.read(1)[0]
    fp.seek(off + byte)
    fp.write(bytes([b ^ mask]))
with h5py.File(file, "r") as f:
    after = f[path][idx]
assert (before.tobytes() != after.tobytes()), "the flip missed the data"
print(f"value {e} of {n}, file byte {off + byte}: {before!r} -> {after!r}")
PY
}
arrays=(/state/positions /state/velocities /state/positions_old /state/velocities_old /state/converged_positions
        /state/converged_positions_prev /state/friction_anchors_plane /state/friction_anchors_pedestal
        /state/broken_segments /history/curve /history/frames)
nflip=0
for a in "${arrays[@]}"; do
  ok=0 flips=""
  for spot in "first 0 0x01" "middle 3 0x5a" "last 7 0x80"; do
    read -r which byte mask <<<"$spot"
    cp "$work/rich/checkpoint.h5" "$work/flipped.h5"
    where="$(flip "$work/flipped.h5" "$a" "$which" "$byte" "$mask" 2>&1)" || { echo "FAIL flip $a $which: $where"; fail=1; continue; }
    log="$(timeout 30 mpiexec -n 2 "$fabric" "${rich[@]}" -output_dir "$work/rich" -restart "$work/flipped.h5" 2>&1)"; rc=$?
    regex="-restart .*flipped.h5: damaged checkpoint: the checksum of $a does not match"
    if [[ $rc -ne 0 && $rc -ne 124 ]] && grep -Eq -- "$regex" <<<"$log" && [[ "$(rich_snapshot)" == "$rich_before" ]]; then
      nflip=$((nflip + 1)) ok=$((ok + 1)) flips+="${flips:+; }$where"
    else echo "FAIL flipped $a ($where): exit $rc (124 = hung), expected a message matching: $regex"; echo "$log" | head -3; fail=1; fi
  done
  [[ $ok -eq 3 ]] && echo "PASS $a: refused with each byte flipped ($flips): $(grep -m1 "fabric: error" <<<"$log")"
done
if mpiexec -n 2 "$fabric" "${rich[@]}" -output_dir "$work/rich" -restart "$work/rich/checkpoint.h5" >/dev/null 2>&1; then echo "PASS $nflip flips of ${#arrays[@]} arrays refused; the unflipped checkpoint restarts its run"
else echo "FAIL the unflipped full checkpoint does not restart its run"; fail=1; fi

# a state array whose data cannot be read (its address moved past the file's end; rewritten with h5py's lzf filter,
# which the HDF5 library lacks): HDF5's error stack from VecLoad on every rank, naming neither -restart nor the file
unreadable() {
  /usr/bin/python3 - "$@" <<'PY'
import sys, struct, h5py
src, dst, how = sys.argv[1:4]
if how == "past_end":
    with h5py.File(src, "r") as f:
        off = f["state/velocities"].id.get_offset()
    b = bytearray(open(src, "rb").read())
    k = b.find(struct.pack("<Q", off))
    assert k >= 0, "the data address is not in the file"
    b[k:k + 8] = struct.pack("<Q", off + 10**7)
    open(dst, "wb").write(b)
else:
    import shutil
    shutil.copy(src, dst)
    with h5py.File(dst, "r+") as f:
        d = f["state/velocities"]
        data, attrs = d[...], dict(d.attrs)
        del f["state/velocities"]
        n = f["state"].create_dataset("velocities", data=data, chunks=True, compression="lzf")
        for k, v in attrs.items():
            n.attrs[k] = v
PY
}
for how in past_end lzf; do
  unreadable "$ck" "$work/unreadable.h5" "$how" || { echo "FAIL cannot make the $how checkpoint"; fail=1; continue; }
  refuse "unreadable_$how" "^fabric: error: -restart .*unreadable.h5: damaged checkpoint: /state/velocities cannot be read$" \
    "${opts[@]}" -output_dir "$work/run" -restart "$work/unreadable.h5"
  log="$(timeout 30 mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/run" -restart "$work/unreadable.h5" 2>&1)"; rc=$?
  if [[ $rc -eq 124 ]] || grep -q "HDF5-DIAG" <<<"$log"; then echo "FAIL unreadable_$how: hung (exit $rc) or printed HDF5's error stack"; fail=1; fi
done

# a fabric.h5 that is not this run's, though of its grid with the frames the checkpoint lists: refused before any
# output is touched. Another run's of other options (its frames had been taken as this run's, the later ones
# replaced); one with a group under /frames that is not a frame, or without its frame count (the directory was
# already changed: curve.csv cut, summary.json replaced, frames dropped)
mpiexec -n 2 "$fabric" "${opts[@]}" -warp_crimp_pct 7 -output_dir "$work/other" >/dev/null || { echo "FAIL the other run failed"; fail=1; }
h5edit() { /usr/bin/python3 -c "import sys, h5py; f = h5py.File(sys.argv[1], 'r+'); exec(sys.argv[2])" "$@"; }
for bad in "other_run:is another run's: its scene_hash [0-9a-f]{16} is not this run's [0-9a-f]{16}" \
           "stray_group:holds /frames/notes, which is not a frame: it is not the file of this run" \
           "no_count:has no frames attribute at its root"; do
  name=${bad%%:*} regex=${bad#*:}
  cp "$work/run/fabric.h5" "$work/run/fabric.keep"
  case $name in
    other_run) cp "$work/other/fabric.h5" "$work/run/fabric.h5" ;;
    stray_group) h5edit "$work/run/fabric.h5" "f['frames'].create_group('notes')" ;;
    no_count) h5edit "$work/run/fabric.h5" "del f.attrs['frames']" ;;
  esac
  before="$(snapshot)"
  refuse "frames_file_$name" "-restart .*checkpoint.h5: .*/run/fabric.h5 $regex" "${opts[@]}" -output_dir "$work/run" -restart "$ck"
  mv "$work/run/fabric.keep" "$work/run/fabric.h5"
done
before="$(snapshot)"

# the checkpoint itself still restarts (so the refusals above were about what they say)
if mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/run" -restart "$ck" >/dev/null 2>&1 && [[ $(wc -l <"$work/run/curve.csv") -eq 7 ]]; then echo "PASS the same checkpoint restarts the run it belongs to"
else echo "FAIL the checkpoint does not restart its own run"; fail=1; fi
exit $fail
