#!/usr/bin/env bash
# disk_full.sh full|readonly FABRIC SCENE: output on a small tmpfs.
#   full: a run with a frame and a checkpoint every load step fills a 1 MiB disk; it must stop
#         with a non-zero exit (not hang), a message naming the file that does not fit, and the
#         last complete checkpoint.h5 readable (h5ls) and good for a restart.
#   readonly: -output_dir on a read-only file system is refused before any computation.
#   first: a 1 MiB disk too small for the grid and first frame of the whole strip is refused before the first
#         load step, naming fabric.h5, with no fabric.h5 left (HDF5's own error after a stall, half written).
# Mounting needs root (or CAP_SYS_ADMIN): where it is not allowed the test says so and exits 77,
# which CTest reports as skipped (SKIP_RETURN_CODE).
set -u
mode="$1"
fabric="$2"
scene="$3"
work="$(mktemp -d)"
disk="$work/disk"
mkdir "$disk"
cleanup() {
  mountpoint -q "$disk" && umount "$disk"
  rm -rf "$work"
}
trap cleanup EXIT
size="size=1m"
[[ $mode == readonly ]] && size="ro,size=64k"
if ! mount -t tmpfs -o "$size" tmpfs "$disk" 2>"$work/mount.log"; then
  echo "SKIPPED: cannot mount a small tmpfs here ($(head -1 "$work/mount.log")): the $mode-disk case needs root"
  exit 77
fi
small=(-scene "$scene" -gauge_mm 20 -width_mm 5 -load_steps 40)
fail=0
if [[ $mode == readonly ]]; then
  log="$(timeout 60 mpiexec -n 2 "$fabric" "${small[@]}" -output_dir "$disk/run" 2>&1)"
  rc=$?
  echo "$log" | head -3
  expected="^fabric: error: -output_dir $disk/run: cannot create the directory $disk/run .Read-only file system."
  grep -Eq -- "$expected" <<<"$log" || { echo "FAIL: the message does not name the read-only directory"; fail=1; }
  ((rc != 0 && rc != 124)) || { echo "FAIL: exit code $rc (124: it hung)"; fail=1; }
  ((fail == 0)) && echo "PASS: a read-only output place is refused up front"
  exit $fail
fi
if [[ $mode == first ]]; then # the whole strip (57 720 crossings): its grid and first frame need ~7 MB
  log="$(timeout 60 mpiexec -n 2 "$fabric" -scene "$scene" -load_steps 2 -output_every 1 -output_dir "$disk/run" 2>&1)"
  rc=$?
  grep -v '^ ' <<<"$log" | head -3
  ((rc != 0 && rc != 124)) || { echo "FAIL: exit code $rc (124: it hung)"; fail=1; }
  expected="^fabric: error: -output_dir $disk/run: the disk is full: .* too little for the next frame of fabric[.]h5"
  grep -Eq -- "$expected" <<<"$log" || { echo "FAIL: no message naming fabric.h5"; fail=1; }
  grep -q "^load step" <<<"$log" && { echo "FAIL: a load step ran before the refusal"; fail=1; }
  [[ -e $disk/run/fabric.h5 ]] && { echo "FAIL: a half-written fabric.h5 was left"; fail=1; }
  ((fail == 0)) && echo "PASS: a disk too small for the first frame is refused before the first load step"
  exit $fail
fi
log="$(timeout 120 mpiexec -n 2 "$fabric" "${small[@]}" -output_every 1 -checkpoint_every 1 \
  -output_dir "$disk/run" 2>&1)"
rc=$?
grep -v '^ ' <<<"$log" | head -3
((rc != 0 && rc != 124)) || { echo "FAIL: exit code $rc (0: the disk never filled; 124: it hung)"; fail=1; }
expected="^fabric: error: -output_dir $disk/run: the disk is full: .* too little for the next .*(checkpoint|fabric)[.]h5"
grep -Eq -- "$expected" <<<"$log" || { echo "FAIL: no message naming the file that does not fit"; fail=1; }
steps=$(grep -c "^checkpoint at load step" <<<"$log")
((steps >= 1)) || { echo "FAIL: the disk filled before the first checkpoint: nothing to keep intact"; fail=1; }
h5ls "$disk/run/checkpoint.h5" >/dev/null || { echo "FAIL: the last checkpoint.h5 is not readable"; fail=1; }
# the checkpoint is whole: a restart from it (elsewhere, without frames) runs to the end
timeout 120 mpiexec -n 2 "$fabric" "${small[@]}" -quiet -output_every 0 -checkpoint_every 0 -output_dir "$work/again" \
  -restart "$disk/run/checkpoint.h5" >/dev/null 2>&1 || {
  echo "FAIL: the restart from the last checkpoint failed"
  fail=1
}
((fail == 0)) && echo "PASS: the full disk stopped the run after $steps checkpoints; the last one is intact"
exit $fail
