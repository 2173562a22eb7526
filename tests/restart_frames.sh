#!/usr/bin/env bash
# Frames when a restart changes the frame options (the 20 x 5 mm strip, 1 rank; the checkpoint within
# load step 4 of 4, -checkpoint_every_te 1500 at its te step 351):
#  1. te frames turned on at the restart: each te frame has the te step and time of the uninterrupted
#     run's frame at that te step (they were counted from the restart);
#  2. frames turned on at the restart: frame 0, the restart's state, is labelled load step 4 and its te
#     step, before load step 4's own frame in time (it was labelled 3, after it);
#  3. te frames turned off at a restart within a load step: the frame times still increase;
# and on the 20 x 5 mm strip to rupture (the checkpoint at load step 60):
#  4. a restart that writes no frames: fabric.h5 and fabric.xmf keep the frames written before the
#     checkpoint and no later one (the stopped run's later frames stayed);
#  5. the same beside a damaged fabric.h5: the run goes on and leaves the file alone;
#  6. the same beside another run's fabric.h5 (other options, the same grid): left alone too;
#  7. the run's own fabric.h5 of a build before its scene_hash attribute: cut as in 4.
set -u
fabric="$1"; strip="$2"; rupture="$3"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
opts=(-scene "$strip" -gauge_mm 20 -width_mm 5 -predict none -load_steps 4 -quiet)
fail=0
frames() { # fabric.xmf: one line per frame, "time load_step te_step"
  /usr/bin/python3 -c '
import re, sys
for g in re.findall(r"<Grid Name=\"frame_\d+\".*?</Grid>", open(sys.argv[1]).read(), re.S):
    v = [re.search(p, g).group(1) for p in (r"<Time [^>]*Value=\"([^\"]*)\"", r"\"load_step\" Value=\"([^\"]*)\"", r"\"te_step\" Value=\"([^\"]*)\"")]
    print("%.12g %s %s" % (float(v[0]), v[1], v[2]))' "$1"
}
check() { if eval "$1"; then echo "PASS $2"; else echo "FAIL $2"; fail=1; fi; }

"$fabric" "${opts[@]}" -output_every 0 -output_te_every 100 -output_dir "$work/ref" || fail=1
"$fabric" "${opts[@]}" -output_every 0 -checkpoint_every_te 1500 -output_dir "$work/te" || fail=1
"$fabric" "${opts[@]}" -output_every 0 -output_te_every 100 -restart "$work/te/checkpoint.h5" -output_dir "$work/te" || fail=1
frames "$work/ref/fabric.xmf" >"$work/ref.txt"; frames "$work/te/fabric.xmf" >"$work/te.txt"
check 'tail -n +2 "$work/te.txt" | grep -qv "^.* 4 0$" && [[ -z "$(tail -n +2 "$work/te.txt" | grep -vxFf "$work/ref.txt")" ]]' \
  "te frames after the restart = the uninterrupted run's: $(tail -n +2 "$work/te.txt" | tr '\n' ';')"

"$fabric" "${opts[@]}" -output_every 0 -checkpoint_every_te 1500 -output_dir "$work/on" || fail=1
"$fabric" "${opts[@]}" -output_every 1 -restart "$work/on/checkpoint.h5" -output_dir "$work/on" || fail=1
frames "$work/on/fabric.xmf" >"$work/on.txt"
check 'awk "NR == 1 { t = \$1; ok = \$2 == 4 && \$3 > 0 } NR == 2 { ok = ok && \$2 == 4 && \$1 > t } END { exit !ok }" "$work/on.txt"' \
  "frame 0 of the restart within load step 4: $(head -1 "$work/on.txt"), then $(sed -n 2p "$work/on.txt") (time, load step, te step)"

# 3. te frames turned off at a restart within load step 4: its end frame comes after the te frames written
#    before the checkpoint (it was at the load step's time, before them)
"$fabric" "${opts[@]}" -output_te_every 100 -checkpoint_every_te 1500 -output_dir "$work/tedown" || fail=1
"$fabric" "${opts[@]}" -output_te_every 0 -restart "$work/tedown/checkpoint.h5" -output_dir "$work/tedown" || fail=1
frames "$work/tedown/fabric.xmf" >"$work/tedown.txt"
check 'awk "NR > 1 && \$1 <= t { bad = 1 } { t = \$1 } END { exit bad || NR < 3 }" "$work/tedown.txt"' \
  "te frames turned off at a restart within load step 4: frame times increase ($(tail -2 "$work/tedown.txt" | tr '\n' ';'))"

# 4. the strip to rupture, stopped after its last checkpoint (load step 60) with later frames written: a restart
#    without frames keeps the checkpoint's frames in fabric.h5 and fabric.xmf, and no later one, and its end line
#    lists them (it listed curve.csv and summary.json only)
ropts=(-scene "$rupture" -gauge_mm 20 -width_mm 5 -quiet -checkpoint_every 30)
"$fabric" "${ropts[@]}" -output_te_every 20 -output_tear_every 10 -output_dir "$work/full" || fail=1
ck_frames=$(h5dump -a /frames "$work/full/checkpoint.h5" 2>/dev/null | sed -n 's/^ *(0): \([0-9]*\)$/\1/p')
cp -r "$work/full" "$work/off" # the run stopped after its last checkpoint, at load step 60, with its later frames
"$fabric" "${ropts[@]}" -output_every 0 -output_te_every 0 -output_tear_every 0 -restart "$work/off/checkpoint.h5" \
  -output_dir "$work/off" >"$work/off.log" || fail=1
kept=$(h5ls "$work/off/fabric.h5/frames" | wc -l); listed=$(grep -c '<Grid Name="frame' "$work/off/fabric.xmf")
all=$(h5ls "$work/full/fabric.h5/frames" | wc -l)
check '[[ -n "$ck_frames" && $kept == "$ck_frames" && $listed == "$ck_frames" && $all -gt $ck_frames ]]' \
  "a restart without frames: fabric.h5 keeps $kept and fabric.xmf lists $listed frames, the checkpoint's $ck_frames (the stopped run wrote $all)"
check '[[ "$(tail -1 "$work/off.log")" == "fabric: results in $work/off/ (curve.csv, summary.json, fabric.h5 and fabric.xmf ($ck_frames frames, from before the checkpoint), checkpoint.h5)" ]]' \
  "a restart without frames lists the frames it kept: $(tail -1 "$work/off.log")"
# 5. the same with fabric.h5 damaged (the advice of a restart with frames, which refuses it): this run writes
#    no frames and leaves the file alone (it stopped on it)
cp -r "$work/full" "$work/bad"; echo "not HDF5" >"$work/bad/fabric.h5"
"$fabric" "${ropts[@]}" -output_every 0 -output_te_every 0 -output_tear_every 0 -restart "$work/bad/checkpoint.h5" \
  -output_dir "$work/bad" >"$work/bad.log" 2>&1; rc=$?
check '[[ $rc == 0 && "$(cat "$work/bad/fabric.h5")" == "not HDF5" && "$(tail -1 "$work/bad.log")" != *fabric.h5* ]]' "a restart without frames beside a damaged fabric.h5 runs and leaves it alone: $(tail -1 "$work/bad.log")"
# 6. the same beside another run's fabric.h5, of the same grid and frame times (warp crimp 7.9 %, not 8 %): left alone
#    (it was cut to the checkpoint's frames: only the frames' names were looked at)
"$fabric" "${ropts[@]}" -warp_crimp_pct 7.9 -output_te_every 20 -output_tear_every 10 -output_dir "$work/other" >/dev/null || fail=1
cp "$work/full/checkpoint.h5" "$work/other/" && sum=$(md5sum <"$work/other/fabric.h5")
"$fabric" "${ropts[@]}" -output_every 0 -output_te_every 0 -output_tear_every 0 -restart "$work/other/checkpoint.h5" \
  -output_dir "$work/other" >"$work/other.log" 2>&1; rc=$?
check '[[ $rc == 0 && "$(md5sum <"$work/other/fabric.h5")" == "$sum" && "$(tail -1 "$work/other.log")" != *fabric.h5* ]]' "a restart without frames beside another run's fabric.h5 (its scene_hash another) runs and leaves it alone ($(h5ls "$work/other/fabric.h5/frames" | wc -l) frames): $(tail -1 "$work/other.log")"
# 7. the run's own fabric.h5 written by a build before scene_hash (the attribute removed): its frames tell it is
#    this run's, and a restart without frames cuts it to the checkpoint's frames as in 4
cp -r "$work/full" "$work/old"
/usr/bin/python3 -c "import sys, h5py; f = h5py.File(sys.argv[1], 'r+'); del f.attrs['scene_hash']" "$work/old/fabric.h5" || fail=1
"$fabric" "${ropts[@]}" -output_every 0 -output_te_every 0 -output_tear_every 0 -restart "$work/old/checkpoint.h5" \
  -output_dir "$work/old" >/dev/null 2>&1 || fail=1
kept=$(h5ls "$work/old/fabric.h5/frames" | wc -l)
check '[[ $kept == "$ck_frames" ]]' "a restart without frames, its run's fabric.h5 of an earlier build (no scene_hash): cut to the checkpoint's $ck_frames frames ($kept)"
exit $fail
