#!/usr/bin/env bash
# output_dir.sh FABRIC SCENE: what a run leaves in -output_dir (docs/output.md)
#  1. a fresh run into a directory that holds an earlier run's results (checkpoint.h5, frames): with
#     no frames and no checkpoints of its own it leaves neither behind, says so (also with -quiet), and its summary.json is its
#     own; a checkpoint.h5 that is not this program's (a text file) stays;
#  2. summary.json is valid JSON when the scene's name holds a tab, a newline (the tab was written raw), a
#     Latin-1 byte (as U+FFFD) and UTF-8;
#  3. a restart that turns frames on, from a run that wrote none: frame 0 is the checkpoint's state at
#     the time_s of its load step in curve.csv (it was that plus the te steps' time);
#  4. a restart whose fabric.h5 is another run's of the same grid (frames at other times: another
#     -speed_mm_min) is refused by its scene_hash; one of this run's options but frames at other
#     load steps (-output_every 2), naming the frame that differs (their frames were mixed in).
#  5. ranks that do not share -output_dir (rank 1 started in another working directory, a relative
#     -output_dir: as a directory on each node's own disk): refused at once, naming the rank, and nothing
#     left in either place (the ranks waited in MPI_File_open for ever).
#  6. a scene file whose name holds a backslash and ${...} is read under that name (PETSc's YAML file reader
#     made the backslash a '/' and expanded ${...}: "not a valid YAML option file: Unable to open" or
#     "Substitution string ... not found"); without -output_dir, its default results/NAME holding '${' is refused
#     naming the scene (the refusal named -output_dir, which was not given).
#  7. a directory in -output_dir under the name of a file the run writes (fabric.h5, .checkpoint.h5.tmp): refused
#     at the start, naming it, the directory's earlier contents untouched (the run failed at its first frame or
#     checkpoint with "Error in HDF5 call H5Fcreate()", its curve.csv and summary.json written)
#  8. an -output_dir path of 260 characters: frames, a checkpoint and a restart from it on 2 ranks (Open MPI 4.1's
#     MPI_File_open aborted a run into a 251-character -output_dir: a buffer overflow in its shared-file-pointer component)
#  9. an -output_dir another run is writing into (it holds DIR/.fabric.lock): refused at the start, naming it, the
#     directory and the -positions_out file as they were; once that run has ended, a run there goes on (the two runs' files were mixed, and the first
#     reported success)
# 10. summary.json that cannot be written at the end of a 2-rank run (a directory under its temporary name, made
#     once the run has written curve.csv rows): every rank stops alike, at once, with one error line naming it, and
#     no summary.json or -positions_out file (rank 0 stopped alone: the others waited 10 s in the positions' scatter,
#     the run was aborted, and the error was printed twice)
set -u
fabric="$1"; scene="$2"
. "$(dirname "$0")/runs.sh" # $py, $work, $fail, run NP ARGS...
small=(-scene "$scene" -gauge_mm 20 -width_mm 5 -load_steps 4)

d="$work/reused"
run 1 "${small[@]}" -output_dir "$d" -checkpoint_every 1 -output_every 1
[[ -e $d/checkpoint.h5 && -e $d/fabric.h5 && -e $d/fabric.xmf ]] || { echo "FAIL the first run wrote no checkpoint or frames"; fail=1; }
mpiexec -n 2 "$fabric" "${small[@]}" -quiet -output_dir "$d" -output_every 0 -balance_tol 1e-4 >"$work/log" 2>&1 \
  || { cat "$work/log"; echo "FAIL the fresh run failed"; fail=1; }
grep -q "^fabric: removed $d/checkpoint.h5, an earlier run's" "$work/log" && grep -q "^fabric: removed $d/fabric.h5" "$work/log" \
  || { cat "$work/log"; echo "FAIL the fresh run did not name the files it removed"; fail=1; }
if [[ -e $d/checkpoint.h5 || -e $d/fabric.h5 || -e $d/fabric.xmf ]]; then
  echo "FAIL a fresh run with no frames or checkpoints left the earlier run's: $(ls "$d")"; fail=1
elif "$py" -c "import json, sys; sys.exit(json.load(open('$d/summary.json'))['options']['balance_tol'] != 1e-4)"; then
  echo "PASS a fresh run replaced the earlier run's results: $(ls "$d" | tr '\n' ' ')"
else
  echo "FAIL summary.json is not the fresh run's"; fail=1
fi

echo "not a checkpoint" >"$d/checkpoint.h5"
run 1 "${small[@]}" -output_dir "$d" -output_every 0
[[ $(cat "$d/checkpoint.h5") == "not a checkpoint" ]] && echo "PASS a checkpoint.h5 that is not this program's stays" \
  || { echo "FAIL a checkpoint.h5 that is not this program's was removed"; fail=1; }

name="$work/$(printf 'tab\there\nline\351-\303\251')"
cp "$scene" "$name.yaml"
run 1 -scene "$name.yaml" -gauge_mm 20 -width_mm 5 -load_steps 2 -output_dir "$work/tab"
"$py" - "$work/tab/summary.json" <<'PY' || fail=1
import json, sys
try:
    s = json.load(open(sys.argv[1], encoding="utf-8")); ok = s["scene"] == "tab\there\nline\ufffd-\u00e9"
except ValueError as e:
    s, ok = str(e), False
print(("PASS" if ok else "FAIL") + f" summary.json with control characters in the scene's name: {s['scene'] if ok else s!r}")
sys.exit(0 if ok else 1)
PY

name="$work/"'back\slash${NO_SUCH_VAR}'
cp "$scene" "$name.yaml"
run 2 -scene "$name.yaml" -gauge_mm 20 -width_mm 5 -load_steps 2 -output_dir "$work/odd"
"$py" - "$work/odd/summary.json" <<'PY' || fail=1
import json, sys
try:
    s = json.load(open(sys.argv[1])); ok = s["scene"] == "back\\slash${NO_SUCH_VAR}" and s["grid"] == [49, 12]
except (OSError, ValueError) as e:
    s, ok = str(e), False
print(("PASS" if ok else "FAIL") + f" a scene file named with a backslash and ${{...}} is read as named: {s['scene'] if ok else s!r}")
sys.exit(0 if ok else 1)
PY
# without -output_dir its default, results/ and the scene's name, holds '${': refused naming the scene (it named
# -output_dir, not given), nothing written
log="$(cd "$work" && mpiexec -n 1 "$fabric" -quiet -scene "$name.yaml" -gauge_mm 20 -width_mm 5 -load_steps 2 2>&1)"
want="fabric: error: -scene $name.yaml: its output directory, results/back\\slash\${NO_SUCH_VAR} (named after the scene file: no -output_dir given), holds '\${'"
if [[ "$log" == "$want"* && ! -e "$work/results" ]]; then echo "PASS its default output directory refused naming the scene"
else echo "FAIL the default output directory of a scene named with \${...}: expected '$want...', got:"; echo "$log"; fail=1; fi

d="$work/late"
run 1 "${small[@]}" -output_dir "$d" -output_every 0 -checkpoint_every 3
run 1 "${small[@]}" -output_dir "$d" -output_every 1 -restart "$d/checkpoint.h5"
"$py" - "$d/fabric.h5" "$d/curve.csv" <<'PY' || fail=1
import csv, sys, h5py
rows = list(csv.DictReader(open(sys.argv[2])))
with h5py.File(sys.argv[1], "r") as f:
    t = [(f["frames"][k].attrs["load_step"].item(), f["frames"][k].attrs["time_s"].item()) for k in sorted(f["frames"])]
want = [(int(r["load_step"]), float(r["time_s"])) for r in rows[2:]]
ok = [(a, round(b, 9)) for a, b in t] == [(a, round(b, 9)) for a, b in want]
print(("PASS" if ok else "FAIL") + f" frames turned on at a restart from load step 3: (load step, time) {t}, curve.csv {want}")
sys.exit(0 if ok else 1)
PY
run 1 "${small[@]}" -output_dir "$work/mixA" -output_every 1 -checkpoint_every 3
run 1 "${small[@]}" -output_dir "$work/mixB" -output_every 1 -speed_mm_min 50
run 1 "${small[@]}" -output_dir "$work/mixC" -output_every 2
for other in "mixB:fabric.h5 is another run's: its scene_hash [0-9a-f]* is not this run's [0-9a-f]*" \
             "mixC:fabric.h5's frame 1 (load step 2, te step .*) is not the one written before the checkpoint (load step 1,"; do
  cp "$work/mixA/fabric.h5" "$work/mixA.keep" && cp "$work/${other%%:*}/fabric.h5" "$work/mixA/fabric.h5"
  if mpiexec -n 1 "$fabric" "${small[@]}" -output_dir "$work/mixA" -output_every 1 -restart "$work/mixA/checkpoint.h5" \
    >"$work/log" 2>&1; then
    echo "FAIL a restart into another run's fabric.h5 (${other%%:*}) was accepted"; fail=1
  elif grep -q "${other#*:}" "$work/log"; then
    echo "PASS a restart into another run's fabric.h5 (${other%%:*}) is refused: $(grep -o "fabric.h5.*" "$work/log")"
  else
    cat "$work/log"; echo "FAIL a restart into another run's fabric.h5 (${other%%:*}): not the expected message"; fail=1
  fi
  mv "$work/mixA.keep" "$work/mixA/fabric.h5"
done
mkdir -p "$work/wd0" "$work/wd1"
scene_abs="$(cd "$(dirname "$scene")" && pwd)/$(basename "$scene")"
timeout 120 mpiexec -n 1 -wdir "$work/wd0" "$fabric" -scene "$scene_abs" -gauge_mm 20 -width_mm 5 -load_steps 4 -output_dir out \
  : -n 1 -wdir "$work/wd1" "$fabric" -scene "$scene_abs" -gauge_mm 20 -width_mm 5 -load_steps 4 -output_dir out >"$work/log" 2>&1
rc=$?
left="$(ls -A "$work/wd0" "$work/wd1" | grep -v '^$\|:$' | tr '\n' ' ')"
if [[ $rc -ne 0 && $rc -ne 124 && -z $left ]] && grep -q "error: -output_dir out: rank 1 does not see the files rank 0 writes there" "$work/log"; then
  echo "PASS ranks that do not share -output_dir: refused (exit $rc), nothing left"
else
  cat "$work/log"; echo "FAIL ranks that do not share -output_dir: exit $rc (124: hung), left: $left"; fail=1
fi
for own in fabric.h5 .checkpoint.h5.tmp; do
  d="$work/own_dir_$own"
  mkdir -p "$d/$own" && echo '{"converged": true}' >"$d/summary.json"
  mpiexec -n 1 "$fabric" "${small[@]}" -checkpoint_every 1 -output_dir "$d" >"$work/log" 2>&1
  rc=$?
  left="$(ls -A "$d" | tr '\n' ' ')"
  if [[ $rc -ne 0 && "$left" == "$own summary.json " ]] && grep -q "^fabric: error: -output_dir $d: $d/$own is a directory, where the run writes its $own" "$work/log"; then
    echo "PASS a directory $own in -output_dir: refused at the start (exit $rc), naming it; the directory as it was"
  else
    cat "$work/log"; echo "FAIL a directory $own in -output_dir: exit $rc, left: $left"; fail=1
  fi
done
d="$work/$(printf 'l%.0s' {1..200})/$(printf 'm%.0s' {1..40})"
run 2 "${small[@]}" -output_dir "$d" -checkpoint_every 2 -output_every 1
run 2 "${small[@]}" -output_dir "$d" -output_every 1 -restart "$d/checkpoint.h5"
if [[ ${#d} -ge 260 && -s $d/fabric.h5 && -s $d/checkpoint.h5 ]] && grep -q '"converged": true' "$d/summary.json"; then
  echo "PASS an -output_dir of ${#d} characters: frames, a checkpoint and a restart on 2 ranks"
else
  echo "FAIL an -output_dir of ${#d} characters: $(ls -A "$d" | tr '\n' ' ')"; fail=1
fi
d="$work/locked"
mkdir -p "$d" && echo '{"converged": true}' >"$d/summary.json"
"$py" -c 'import fcntl, sys, time; f = open(sys.argv[1], "a"); fcntl.lockf(f, fcntl.LOCK_EX); open(sys.argv[2], "w").close(); time.sleep(60)' \
  "$d/.fabric.lock" "$work/held" &
holder=$!
for t in $(seq 100); do [[ -e $work/held ]] && break; sleep 0.1; done
echo "an earlier run's positions" >"$work/pos.bin"
mpiexec -n 2 "$fabric" "${small[@]}" -output_dir "$d" -positions_out "$work/pos.bin" >"$work/log" 2>&1
rc=$?
left="$(ls -A "$d" | tr '\n' ' ')"
if [[ $rc -ne 0 && "$left" == ".fabric.lock summary.json " && -s $work/pos.bin ]] &&
  grep -q "^fabric: error: -output_dir $d: another run is writing there (it holds $d/.fabric.lock); give each run its own -output_dir" "$work/log"; then
  echo "PASS an -output_dir another run holds: refused at the start (exit $rc), naming it; the directory as it was"
else
  cat "$work/log"; echo "FAIL an -output_dir another run holds: exit $rc, left: $left"; fail=1
fi
kill "$holder"; wait "$holder" 2>/dev/null
run 2 "${small[@]}" -output_dir "$d"
if grep -q '"scene": "strip_warp"' "$d/summary.json"; then
  echo "PASS once the other run has ended, a run in that -output_dir goes on"
else
  echo "FAIL once the other run has ended: summary.json is not this run's"; fail=1
fi
d="$work/summary_fails"
mkdir -p "$d"
mpiexec -n 2 "$fabric" -scene "$scene" -load_steps 200 -output_every 0 -quiet -output_dir "$d" -positions_out "$d/pos.bin" \
  >"$work/log" 2>&1 &
runner=$!
for t in $(seq 600); do [[ -s $d/curve.csv && $(wc -l <"$d/curve.csv") -ge 3 ]] && break; sleep 0.05; done
mkdir "$d/.summary.json.tmp"
wait "$runner"
rc=$?
lines=$(grep -c "^fabric: error" "$work/log")
if [[ $rc -ne 0 && $lines -eq 1 && ! -e $d/summary.json && ! -e $d/pos.bin ]] &&
  grep -q "^fabric: error: -output_dir $d: cannot create summary.json (Is a directory)$" "$work/log" &&
  ! grep -q "did not stop" "$work/log"; then
  echo "PASS summary.json not writable at the end on 2 ranks: one error line, every rank stopped (exit $rc), no summary.json or positions"
else
  cat "$work/log"; echo "FAIL summary.json not writable at the end: exit $rc, $lines error lines, left: $(ls -A "$d" | tr '\n' ' ')"; fail=1
fi
exit $fail
