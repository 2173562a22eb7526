#!/usr/bin/env bash
# output_render.sh FABRIC SCENE: scripts/render.py (pvbatch on an Xvfb display) renders frames of a run
# coloured by warp tension, and three steps of a coarse pushing test side by side (the paper's
# figure 11, --panel); scripts/plot_curve.py draws force vs elongation of two runs with a
# measured curve overlaid; tests/check_png.py checks that the images show what they should.
set -u
fabric="$1"; scene="$2"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"; root="$(dirname "$here")"
work="$(mktemp -d)"; xpid=""
trap '[[ -n "$xpid" ]] && kill "$xpid" 2>/dev/null && wait "$xpid" 2>/dev/null; rm -rf "$work"' EXIT
# One X server for the test's renders: Xvfb picks a free display itself and writes its number on
# fd 3 once it accepts connections (-displayfd: no race with other servers starting), and does not
# reset when a client leaves (-noreset: pvbatch connecting while it reset failed with "bad X server
# connection", seen on a loaded machine)
Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp -noreset 3>"$work/display" 2>"$work/xvfb.log" &
xpid=$!
for ((n = 0; n < 1200; n++)); do # at most 2 minutes
  [[ -s "$work/display" ]] && break
  kill -0 "$xpid" 2>/dev/null || { echo "FAIL Xvfb did not start:"; cat "$work/xvfb.log"; exit 1; }
  sleep 0.1
done
[[ -s "$work/display" ]] || { echo "FAIL Xvfb gave no display within 2 minutes"; exit 1; }
export DISPLAY=":$(head -n 1 "$work/display")"
fail=0
opts=(-scene "$scene" -quiet -gauge_mm 20 -width_mm 5 -load_steps 6)
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/a" >/dev/null || { echo "FAIL the run failed"; exit 1; }
mpiexec -n 2 "$fabric" "${opts[@]}" -warp_crimp_pct 4 -output_dir "$work/b" -output_every 0 >/dev/null || { echo "FAIL the second run failed"; exit 1; }

pvbatch "$root/scripts/render.py" "$work/a" --frames 0,last --size 800x450 --out "$work/img/frame" >"$work/render.log" 2>&1 || { echo "FAIL render.py failed:"; cat "$work/render.log"; fail=1; }
cat "$work/render.log"
/usr/bin/python3 "$here/check_png.py" render "$work/img/frame_000000.png" "$work/img/frame_000006.png" 800x450 || fail=1
# a frame that does not exist: a clear message and a non-zero exit
if pvbatch "$root/scripts/render.py" "$work/a" --frames 7 >"$work/bad.log" 2>&1 || ! grep -q "frame 7 does not exist" "$work/bad.log"; then
  echo "FAIL render.py --frames 7 (of 0..6) did not fail with a message"; fail=1
else echo "PASS render.py --frames 7 refused: $(grep "does not exist" "$work/bad.log")"; fi
# an image that cannot be written (/proc takes no new file): exit 1 naming it (VTK logged why, and
# render.py printed the file and exited 0); a file where the folder should be: refused before rendering
for c in "--out /proc/frame|1|render.py: /proc/frame_000006.png: the image could not be written" \
         "--out $work/bad/frame --panel /proc/panel.png|1|render.py: --panel /proc/panel.png: the image could not be written" \
         "--out $work/a/curve.csv/frame|1|render.py: --out $work/a/curve.csv/frame: $work/a/curve.csv: not a directory"; do
  IFS="|" read -r ropts want_rc want <<<"$c"
  # shellcheck disable=SC2086
  pvbatch "$root/scripts/render.py" "$work/a" --frames last --size 200x150 $ropts >"$work/bad.log" 2>"$work/bad.err"; rc=$?
  if [[ $rc -eq $want_rc && "$(tail -n 1 "$work/bad.err")" == "$want" ]]; then echo "PASS render.py $ropts: exit $rc, $want"
  else echo "FAIL render.py $ropts: exit $rc (expected $want_rc), expected '$want' last:"; cat "$work/bad.log" "$work/bad.err"; fail=1; fi
done

# fabric.h5 empty, or cut in half (a run stopped while writing it): said (it named --field warp_tension, not given)
cp -r "$work/a" "$work/cut" && : >"$work/cut/fabric.h5"
cp -r "$work/a" "$work/half" && truncate -s $(($(stat -c %s "$work/a/fabric.h5") / 2)) "$work/half/fabric.h5"
# the last frame cut by the superblock's end of file, as a run killed while writing it leaves it (an AttributeError
# traceback: its fields were None)
cp -r "$work/a" "$work/eoa" && /usr/bin/python3 - "$work/eoa/fabric.h5" <<'PY' || { echo "FAIL could not cut eoa/fabric.h5"; fail=1; }
import h5py, struct, sys
with h5py.File(sys.argv[1], "r") as f:
    addr = h5py.h5o.get_info(f["frames/000006"].id).addr
with open(sys.argv[1], "r+b") as fh:
    assert fh.read(9)[8] == 0  # superblock version 0: the end-of-file address at byte 40
    fh.seek(40)
    fh.write(struct.pack("<Q", addr))
PY
for c in "cut|render.py: $work/cut/fabric.h5: empty (the run that wrote it stopped before its first frame?)" \
         "half|render.py: $work/half/fabric.xmf and $work/half/fabric.h5 give no field: damaged or cut short (a run stopped while writing them?)" \
         "eoa|render.py: frame 6 of $work/eoa/fabric.xmf: warp_tension cannot be read from $work/eoa/fabric.h5 (a run killed while writing that frame?); choose others with --frames"; do
  d="${c%%|*}" want="${c#*|}"
  pvbatch "$root/scripts/render.py" "$work/$d" --frames last --size 200x150 >"$work/bad.log" 2>"$work/bad.err"; rc=$?
  if [[ $rc -eq 1 && "$(tail -n 1 "$work/bad.err")" == "$want" ]]; then echo "PASS render.py on $d fabric.h5: exit $rc, $want"
  else echo "FAIL render.py on $d fabric.h5: exit $rc (expected 1), expected '$want', last:"; tail -3 "$work/bad.err"; fail=1; fi
done

# the paper's figure 11: three steps of a coarse pushing test side by side (render.py --panel)
mpiexec -n 2 "$fabric" -scene "$root/inputs/pushing.yaml" -quiet -ends_per_cm 6 -picks_per_cm 6 -load_steps 6 -output_every 2 -output_dir "$work/p" >/dev/null || { echo "FAIL the pushing run failed"; exit 1; }
pvbatch "$root/scripts/render.py" "$work/p" --frames 1,2,last --size 400x300 --out "$work/pimg/frame" --panel "$work/fig11.png" >"$work/panel.log" 2>&1 || { echo "FAIL render.py --panel failed:"; cat "$work/panel.log"; fail=1; }
cat "$work/panel.log"
/usr/bin/python3 "$here/check_png.py" panel "$work/fig11.png" 3 400x300 || fail=1

# a vector field is coloured by its magnitude: the scale reaches the largest |displacement| of the frame
pvbatch "$root/scripts/render.py" "$work/p" --frames last --field displacement --size 400x300 --out "$work/pdisp/frame" >"$work/disp.log" 2>&1 || { echo "FAIL render.py --field displacement failed:"; cat "$work/disp.log"; fail=1; }
hi="$(sed -n 's/^render.py: colour scale of displacement: .* to //p' "$work/disp.log")"
/usr/bin/python3 - "$work/p/fabric.h5" "${hi:-nan}" <<'PY' || fail=1
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    last = sorted(f["frames"].keys())[-1]
    u = np.linalg.norm(f["frames"][last]["displacement"][...], axis=-1).max()
hi = float(sys.argv[2])
ok = abs(hi - u) <= 1e-6 * u
print(("PASS" if ok else "FAIL") + f" the displacement's colour scale ends at {hi:.9g} m, its largest magnitude is {u:.9g} m")
sys.exit(0 if ok else 1)
PY
# a colour scale with a negative end, given as "--range LO,HI" (not only "--range=LO,HI")
if pvbatch "$root/scripts/render.py" "$work/p" --frames last --range -5,5 --size 400x300 --out "$work/prange/frame" >"$work/range.log" 2>&1 &&
  grep -q "^render.py: colour scale of warp_tension: -5 to 5$" "$work/range.log"; then
  echo "PASS render.py --range -5,5: $(grep colour "$work/range.log")"
else echo "FAIL render.py --range -5,5:"; cat "$work/range.log"; fail=1; fi
# a run with one frame (it stopped with an error after frame 0): render.py draws it
mpiexec -n 2 "$fabric" "${opts[@]}" -integrator damped -te_check false -te 1e-5 -output_every 1 -output_dir "$work/one" >/dev/null 2>&1
if pvbatch "$root/scripts/render.py" "$work/one" --size 400x300 --out "$work/oneimg/frame" >"$work/one.log" 2>&1 && [[ -s "$work/oneimg/frame_000000.png" ]]; then
  echo "PASS render.py drew the one frame of a run that stopped after it"
else echo "FAIL render.py on a one-frame run:"; cat "$work/one.log"; fail=1; fi

printf "elongation_pct,force_N\n2,0.5\n6,2.3\n9,9.5\n12,24\n" >"$work/measured.csv"
/usr/bin/python3 "$root/scripts/plot_curve.py" "$work/a/curve.csv" "$work/b/curve.csv" --labels "crimp 8 %,crimp 4 %" --measured "$work/measured.csv" -o "$work/curve.png" || fail=1
/usr/bin/python3 "$here/check_png.py" plot "$work/curve.png" || fail=1
# curves that cannot share axes, a curve without rows, a drape's curve: refused, saying why
printf "load_step,time_s,elongation_pct,force_N,inner_steps,residual\n" >"$work/empty.csv"
printf "load_step,time_s,drop_mm,force_N,inner_steps,residual\n1,0,50,0,10,1e-7\n" >"$work/drape.csv"
for c in "$work/a/curve.csv $work/p/curve.csv|mix elongation_pct and travel_mm" "$work/empty.csv|no load step in it" \
         "$work/drape.csv|a drape run's curve"; do
  files="${c%%|*}"; want="${c#*|}"
  # shellcheck disable=SC2086
  if /usr/bin/python3 "$root/scripts/plot_curve.py" $files -o "$work/bad.png" >"$work/plot.log" 2>&1 || ! grep -q "$want" "$work/plot.log"; then
    echo "FAIL plot_curve.py on $files: not refused with '$want':"; cat "$work/plot.log"; fail=1
  else echo "PASS plot_curve.py refused: $(cat "$work/plot.log")"; fi
done
# a measured curve with a nan or inf row, after the data or before it: refused naming the line (it was plotted
# without the point)
printf "elongation_pct,force_N\n2,0.5\n6,nan\n" >"$work/measured_nan.csv"
printf "elongation_pct,force_N\ninf,0.5\n6,1\n" >"$work/measured_inf.csv"
for m in "measured_nan.csv line 3" "measured_inf.csv line 2"; do
  if /usr/bin/python3 "$root/scripts/plot_curve.py" "$work/a/curve.csv" --measured "$work/${m%% *}" -o "$work/bad.png" \
    >"$work/plot.log" 2>&1 || ! grep -q "$m: expected two finite numbers" "$work/plot.log"; then
    echo "FAIL plot_curve.py --measured ${m%% *}: not refused naming ${m#* }:"; cat "$work/plot.log"; fail=1
  else echo "PASS plot_curve.py refused: $(cat "$work/plot.log")"; fi
done
exit $fail
